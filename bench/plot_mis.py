#!/usr/bin/env python3
"""Plot of bench_mis' and bench_reference_mis' CSVs (docs/mis.md, "Measured").

    /usr/bin/python3 bench/plot_mis.py [RESULTS_DIR]

Reads RESULTS_DIR/mis.csv (default bench/results; the kernels' MIS at equal time) and, when present,
RESULTS_DIR/reference_mis.csv (the reference renderer's MIS at equal samples) and writes
RESULTS_DIR/mis.png: per surface (GGX roughness, Lambert at the right), the rel. MSE of each `mis`
setting, with the reference's own noise as a dotted line, and the ratio none / setting (> 1: MIS
wins; the dashed line at 4 is issue 27's target below roughness 0.05).
"""
import csv
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SETTINGS = ["none", "balance", "power"]
STYLE = {"none": ("k", "o"), "balance": ("tab:blue", "s"), "power": ("tab:red", "^")}


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def x_of(material, lambert_x):
    """GGX roughness as x; Lambert at lambert_x (right of every GGX point)."""
    kind, _, value = material.partition(" ")
    return float(value) if kind == "ggx" else lambert_x


def series(rows, column):
    """{setting: sorted [(x, value)]} and the reference noise per x."""
    lambert_x = 2.0
    out, noise = defaultdict(list), {}
    for r in rows:
        x = x_of(r["material"], lambert_x)
        out[r["mis"]].append((x, float(r[column])))
        noise[x] = float(r["reference_noise_rel_mse"])
    return {k: sorted(v) for k, v in out.items()}, sorted(noise.items())


def panel_error(ax, rows, column, title):
    s, noise = series(rows, column)
    for name in SETTINGS:
        if name in s:
            c, m = STYLE[name]
            ax.plot(*zip(*s[name]), color=c, marker=m, label=name)
    ax.plot(*zip(*noise), "k:", label="reference noise")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("GGX roughness (Lambert at 2)")
    ax.set_ylabel(column.replace("_", " "))
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)


def panel_ratio(ax, rows, column, title):
    s, _ = series(rows, column)
    base = dict(s.get("none", []))
    for name in SETTINGS[1:]:
        if name in s:
            c, m = STYLE[name]
            pts = [(x, base[x] / v) for x, v in s[name] if x in base and v > 0]
            ax.plot(*zip(*pts), color=c, marker=m, label=f"none / {name}")
    ax.axhline(4.0, color="gray", ls="--", lw=0.8, label="target 4x (roughness <= 0.05)")
    ax.axhline(1.0, color="k", lw=0.5)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("GGX roughness (Lambert at 2)")
    ax.set_ylabel("rel. MSE of none / setting")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7)


def main():
    results = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "results")
    kernels = read(os.path.join(results, "mis.csv"))
    ref_path = os.path.join(results, "reference_mis.csv")
    reference = read(ref_path) if os.path.exists(ref_path) else []
    scenes = sorted({r["scene"] for r in reference})
    cols = 2
    rows = 1 + len(scenes)
    fig, axes = plt.subplots(rows, cols, figsize=(10, 3.6 * rows), squeeze=False)
    panel_error(axes[0][0], kernels, "equal_time_rel_mse", "kernels, wet road: equal-time rel. MSE")
    panel_ratio(axes[0][1], kernels, "equal_time_rel_mse", "kernels, wet road: gain at equal time")
    for i, scene in enumerate(scenes, start=1):
        part = [r for r in reference if r["scene"] == scene]
        panel_error(axes[i][0], part, "rel_mse", f"nearfield reference, {scene}: rel. MSE at equal samples")
        panel_ratio(axes[i][1], part, "rel_mse", f"nearfield reference, {scene}: gain at equal samples")
    fig.tight_layout()
    out = os.path.join(results, "mis.png")
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main()
