#!/usr/bin/env python3
"""Before/after table of env_diffuse sh's lights (docs/environment.md, "Small bright lights").

Reads RESULTS_DIR/environment_scenes.csv (written by bench_env_scenes; default bench/results) and
writes RESULTS_DIR/environment_sh_lights.md: for the glossy floor (fis, N = 32, sh diffuse) and
the Lambert floor (sh diffuse), the relative bias of the total light against the reference with
the SH alone (the `sh-lights-0` rows: env_sh_lights 0, the behaviour before) and with
the default 64 lights, the reference's standard error beside them, and the rel. MSE of both.
Usage: bench/env_sh_lights_table.py [RESULTS_DIR]
"""
import csv
import os
import sys


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "results")
    with open(os.path.join(out, "environment_scenes.csv")) as f:
        rows = list(csv.DictReader(f))
    pairs = {"plane": ("fis sh-lights-0", "fis"), "floor": ("diffuse-sh sh-lights-0", "diffuse-sh")}
    found = {}
    for r in rows:
        if r["target"] not in pairs or int(r["n"]) != 32:
            continue
        before, after = pairs[r["target"]]
        key = (r["target"], r["hdri"], float(r["roughness"]))
        if r["method"] == before:
            found.setdefault(key, {})["before"] = r
        elif r["method"] == after:
            found.setdefault(key, {})["after"] = r
    lines = [
        "# env_diffuse sh: the SH alone against the SH with the 64 brightest blocks as lights",
        "",
        "From environment_scenes.csv (bench_env_scenes; machine, load and references in "
        "environment_scenes.md). N = 32, fis glossy, sh diffuse, one frame; before = "
        "env_sh_lights 0 in the same run. Written by bench/env_sh_lights_table.py.",
        "",
        "| target | HDRI | roughness | bias before | bias after | reference s.e. | rel. MSE before | after |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for key in sorted(found):
        v = found[key]
        if "before" not in v or "after" not in v:
            continue
        b, a = v["before"], v["after"]
        rough = f"{key[2]:g}" if key[2] >= 0 else "-"
        lines.append(
            f"| {key[0]} | {key[1]} | {rough} | {100 * float(b['rel_bias']):+.2f} % | "
            f"{100 * float(a['rel_bias']):+.2f} % | {100 * float(a['reference_total_se']):.2f} % | "
            f"{float(b['rel_mse']):.2e} | {float(a['rel_mse']):.2e} |"
        )
    with open(os.path.join(out, "environment_sh_lights.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
