#!/usr/bin/env python3
"""Checks that a bench_sweep + plot_report run left well-formed outputs (the ctest smoke test).

    bench/check_sweep_outputs.py RESULTS_DIR

Checks existence and form only, never timings: the CSV tables have their columns and one row per
planned point (meta.json 'points'), numbers parse, errors are finite and >= 0, every target has a
reference, the PNGs are PNG files, report.md names the machine and has the headline section.
Exit status 0 when all holds; otherwise prints every problem and exits 1.
"""
import csv
import json
import math
import os
import sys

POINT_COLUMNS = [
    "study", "target", "kind", "luminaire", "width", "height", "method", "sampler", "balance", "search",
    "search_depth", "k_max", "structure", "K", "frames", "spp", "reps", "samples", "samples_per_pixel",
    "step0_ms", "step1_ms", "step2_ms", "cl_other_ms", "accumulate_ms", "time_ms", "time_median_ms", "wall_ms", "cpu_ms",
    "samples_per_s", "delta_e", "delta_e_max", "rel_mse", "rel_bias", "ref_key",
]
REFERENCE_COLUMNS = [
    "target", "kind", "luminaire", "width", "height", "key", "file", "from_cache", "spp", "frames", "render_ms",
    "samples", "valid_pixels", "mean_luminance", "noise_rel_mse", "noise_delta_e",
]
BREAKDOWN_COLUMNS = ["target", "structure", "spp", "rep", "category", "ms"]
PLOTS = ["error_vs_spp.png", "error_vs_time.png", "relmse_vs_spp.png", "relmse_vs_time.png", "breakdown.png",
         "studies.png"]
METHODS = {"ours", "paper", "uniform", "uniform-equal", "ours-equal", "global"}
SAMPLERS = {"halton", "halton-scrambled", "random"}


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    problems = []

    def need(cond, msg):
        if not cond:
            problems.append(msg)
        return cond

    def table(name, columns):
        path = os.path.join(out, name)
        if not need(os.path.isfile(path), f"{name}: missing"):
            return []
        with open(path, newline="") as f:
            reader = csv.reader(f)
            rows = list(reader)
        if not need(rows, f"{name}: empty"):
            return []
        need(rows[0] == columns, f"{name}: columns {rows[0]} != {columns}")
        for i, r in enumerate(rows[1:], start=2):
            need(len(r) == len(columns), f"{name}:{i}: {len(r)} values for {len(columns)} columns")
        return [dict(zip(rows[0], r)) for r in rows[1:]]

    meta = {}
    mp = os.path.join(out, "meta.json")
    if need(os.path.isfile(mp), "meta.json: missing"):
        with open(mp) as f:
            meta = json.load(f)
        need(meta.get("complete") is True, "meta.json: the sweep did not complete")
        for k in ("cpu_model", "cores", "cl_device", "git_commit", "date_utc"):
            need(k in meta.get("machine", {}), f"meta.json: machine.{k} missing")

    points = table("points.csv", POINT_COLUMNS)
    refs = table("references.csv", REFERENCE_COLUMNS)
    table("breakdown.csv", BREAKDOWN_COLUMNS)

    if meta:
        need(len(points) == meta.get("points"), f"points.csv: {len(points)} rows, plan had {meta.get('points')}")
    targets = {p.get("target") for p in points}
    ref_targets = {r.get("target") for r in refs}
    need(targets <= ref_targets, f"references.csv: no reference for {sorted(targets - ref_targets)}")
    for i, p in enumerate(points, start=2):
        need(p.get("method") in METHODS, f"points.csv:{i}: method '{p.get('method')}'")
        need(p.get("sampler") in SAMPLERS, f"points.csv:{i}: sampler '{p.get('sampler')}'")
        for k in ("K", "frames", "spp", "samples", "reps"):
            try:
                need(int(p[k]) >= 0, f"points.csv:{i}: {k} < 0")
            except (KeyError, ValueError):
                problems.append(f"points.csv:{i}: {k} = '{p.get(k)}' is not an integer")
        try:
            need(int(p["spp"]) == int(p["K"]) * int(p["frames"]), f"points.csv:{i}: spp != K * frames")
        except (KeyError, ValueError):
            pass
        for k in ("delta_e", "delta_e_max", "rel_mse"):
            try:
                v = float(p[k])
                need(math.isfinite(v) and v >= 0, f"points.csv:{i}: {k} = {v}")
            except (KeyError, ValueError):
                problems.append(f"points.csv:{i}: {k} = '{p.get(k)}' is not a number")
        for k in ("rel_bias", "time_ms", "samples_per_s", "step1_ms", "step2_ms"):
            try:
                need(math.isfinite(float(p[k])), f"points.csv:{i}: {k} not finite")
            except (KeyError, ValueError):
                problems.append(f"points.csv:{i}: {k} = '{p.get(k)}' is not a number")
    for i, r in enumerate(refs, start=2):
        try:
            need(int(r["spp"]) > 0, f"references.csv:{i}: spp")
            need(float(r["noise_rel_mse"]) >= 0, f"references.csv:{i}: noise_rel_mse")
        except (KeyError, ValueError):
            problems.append(f"references.csv:{i}: bad number")

    for name in PLOTS:
        path = os.path.join(out, name)
        if need(os.path.isfile(path), f"{name}: missing"):
            with open(path, "rb") as f:
                head = f.read(8)
            need(head == b"\x89PNG\r\n\x1a\n", f"{name}: not a PNG file")
            need(os.path.getsize(path) > 1000, f"{name}: suspiciously small")

    rp = os.path.join(out, "report.md")
    if need(os.path.isfile(rp), "report.md: missing"):
        with open(rp, encoding="utf-8") as f:
            text = f.read()
        for heading in ("## Machine", "## Ablation", "## Headline ratios", "## Figures"):
            need(heading in text, f"report.md: no '{heading}' section")
        if meta:
            need(meta.get("machine", {}).get("cpu_model", "?") in text, "report.md: does not name the CPU")
        for name in PLOTS:
            need(f"({name})" in text, f"report.md: does not show {name}")

    if problems:
        print(f"check_sweep_outputs: {len(problems)} problem(s) in {out}:")
        for p in problems:
            print(f"  - {p}")
        sys.exit(1)
    print(f"check_sweep_outputs: {out}: {len(points)} points, {len(refs)} references, {len(PLOTS)} plots, report OK")


if __name__ == "__main__":
    main()
