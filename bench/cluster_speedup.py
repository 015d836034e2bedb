#!/usr/bin/env python3
"""Parts per second and speed-up of `cluster/nearfield-cluster reference` on a local Ray with 1 and
2 CPUs (docs/cluster.md, "Measured"): the default scene, fresh part caches, per-part seconds from
the progress lines. Run with the project's venv Python (scripts/setup_python.sh).

    bench/cluster_speedup.py [--spp 256] [--parts 8] [--size 320x180] [--cpus 1,2] [--out CSV]
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--spp", type=int, default=256)
    p.add_argument("--parts", type=int, default=8)
    p.add_argument("--size", default="320x180")
    p.add_argument("--cpus", default="1,2")
    p.add_argument("--out")
    o = p.parse_args()
    w, h = o.size.split("x")
    rows = []
    for cpus in [int(c) for c in o.cpus.split(",")]:
        with tempfile.TemporaryDirectory() as d:
            cmd = [sys.executable, os.path.join(ROOT, "cluster", "nearfield-cluster"), "reference",
                   os.path.join(ROOT, "scenes", "default.json"), "--width", w, "--height", h, "--spp", str(o.spp),
                   "--parts", str(o.parts), "--num-cpus", str(cpus), "--cache", os.path.join(d, "cache"),
                   "--ray-temp-dir", os.path.join(d, "ray"), "-o", os.path.join(d, "out.exr")]
            start = time.time()
            r = subprocess.run(cmd, capture_output=True, text=True)
            wall = time.time() - start
            if r.returncode != 0:
                sys.exit(f"cluster_speedup: {r.stderr.strip()}")
            parts = [float(s) for s in re.findall(r"done on \S+ in ([0-9.]+) s", r.stderr)]
            m = re.search(r"in ([0-9.]+) s; wrote", r.stdout)
            ray_and_parts = float(m.group(1)) if m else float("nan")
            rows.append((cpus, wall, ray_and_parts, len(parts) / ray_and_parts, sum(parts), min(parts), max(parts)))
    load = open("/proc/loadavg").read().split()[:3]
    lines = [f"# {o.size}, {o.spp} spp, {o.parts} parts, default scene; local Ray; {os.cpu_count()} CPUs, "
             f"load average {' '.join(load)} at the end; {time.strftime('%Y-%m-%dT%H:%M:%SZ', time.gmtime())}",
             "ray_cpus,wall_s,ray_and_parts_s,parts_per_s,part_s_sum,part_s_min,part_s_max,speedup_vs_first"]
    for r in rows:
        lines.append(",".join(f"{v:.3g}" if isinstance(v, float) else str(v) for v in r) +
                     f",{rows[0][2] / r[2]:.2f}")
    text = "\n".join(lines) + "\n"
    print(text, end="")
    if o.out:
        with open(o.out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()
