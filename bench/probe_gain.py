#!/usr/bin/env python3
"""`ours` against `uniform` on one luminaire, through `nearfield probe` alone (no bench build).

Usage: bench/probe_gain.py NEARFIELD LUMINAIRE.json [FIRST_SEED]

The points are the close-up wall of bench/sweep/closeup.h (z = 2 delta, facing the luminaire,
+-40 degrees plus a quarter of the image), on an 8 x 8 grid. Each method estimates E at every
point with K = 32 samples for 8 seeds; the relative MSE against `--reference` (points with at
least 1e-3 of the brightest reference value) is averaged over points and seeds. `uniform` samples
each box B_m(p) uniformly with the same K_m as `ours`, so the ratio uniform/ours is what
importance sampling by Y_m inside the boxes gains (docs/measured-data.md).
"""
import json
import math
import subprocess
import sys
import tempfile


def main():
    nf, manifest = sys.argv[1], sys.argv[2]
    first = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    m = json.load(open(manifest))
    dist = 2 * m["delta"]
    half = dist * math.tan(math.radians(40)) + 0.25 * max(m["image"]["size"])
    g = 8
    pts = [(half * (1 - 2 * (gx + 0.5) / g), half * (1 - 2 * (gy + 0.5) / g), dist) for gy in range(g) for gx in range(g)]
    with tempfile.NamedTemporaryFile("w", suffix=".txt", delete=False) as f:
        f.write("".join(f"{x} {y} {z} 0 0 -1\n" for x, y, z in pts))
        points = f.name

    def run(args):
        out = subprocess.run([nf, "probe", manifest, "--points", points] + args, capture_output=True, text=True)
        if out.returncode:
            sys.exit(out.stderr)
        return [float(line.split()[0]) for line in out.stdout.strip().splitlines()]

    ref = run(["--reference"])
    floor = 1e-3 * max(ref)
    mse = {}
    for method in ("ours", "uniform"):
        se, n = 0.0, 0
        for seed in range(first, first + 8):
            for a, r in zip(run(["--method", method, "--spp", "32", "--seed", str(seed)]), ref):
                if r > floor:
                    se += ((a - r) / r) ** 2
                    n += 1
        mse[method] = se / n
    print(f"{m['name']}: relative MSE ours {mse['ours']:.4g}, uniform {mse['uniform']:.4g}, "
          f"uniform/ours {mse['uniform'] / mse['ours']:.3g} (64 wall points, K = 32, seeds {first}..{first + 7})")


if __name__ == "__main__":
    main()
