#!/usr/bin/env python3
"""Plots of bench_env_scenes' CSV (docs/environment.md, "Scene benchmark").

    /usr/bin/python3 bench/plot_env_scenes.py [RESULTS_DIR]

Reads RESULTS_DIR/environment_scenes.csv (default bench/results) and writes
  environment_scenes.png       rel. MSE vs N (log-log), one panel per scene and HDRI, one line per
                               method; the reference's own noise as a dotted line
  environment_scenes_sh.png    the SH visibility: dE vs N_v per HDRI, 'none' as a dashed line
and appends to environment_scenes.md a summary computed from the CSV: per scene, the method with
the lowest rel. MSE at the smallest and at the largest N, and the median over HDRIs of each
method's fitted slope of log rel. MSE against log N (an unbiased estimator whose error is its
variance has slope -1; a flat curve means bias or the reference's noise dominates).
"""
import csv
import math
import os
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

METHODS = ["fis", "fis-rotated", "mc", "env-is", "env-fis", "env-fis-integral"]


def scene_label(row):
    r = float(row["roughness"])
    return row["target"] + (f" r={r:g}" if r >= 0 else "")


def slope(xs, ys):
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x > 0 and y > 0]
    if len(pts) < 2:
        return float("nan")
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx if sxx > 0 else float("nan")


def median(v):
    v = sorted(x for x in v if not math.isnan(x))
    if not v:
        return float("nan")
    k = len(v) // 2
    return v[k] if len(v) % 2 else 0.5 * (v[k - 1] + v[k])


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "results")
    with open(os.path.join(out, "environment_scenes.csv")) as f:
        rows = list(csv.DictReader(f))
    glossy = [r for r in rows if r["target"] != "shadow"]
    shadow = [r for r in rows if r["target"] == "shadow"]
    scenes = sorted({scene_label(r) for r in glossy})
    hdris = sorted({r["hdri"] for r in rows})
    curves = defaultdict(list)  # (scene, hdri, method) -> [(n, rel_mse)]
    noise = {}
    for r in glossy:
        curves[(scene_label(r), r["hdri"], r["method"])].append((int(r["n"]), float(r["rel_mse"])))
        noise[(scene_label(r), r["hdri"])] = float(r["reference_noise_rel_mse"])

    if glossy:
        fig, axes = plt.subplots(len(scenes), len(hdris), figsize=(3.2 * len(hdris), 2.6 * len(scenes)),
                                 squeeze=False, sharex=True)
        for i, s in enumerate(scenes):
            for j, h in enumerate(hdris):
                ax = axes[i][j]
                for m in METHODS:
                    pts = sorted(curves.get((s, h, m), []))
                    if pts:
                        ax.loglog([p[0] for p in pts], [p[1] for p in pts], marker="o", ms=3, label=m)
                if (s, h) in noise and noise[(s, h)] > 0:
                    ax.axhline(noise[(s, h)], color="k", ls=":", lw=1, label="reference noise")
                ax.set_title(f"{s}\n{h.replace('_1k.hdr', '')}", fontsize=8)
                ax.tick_params(labelsize=7)
                if i == len(scenes) - 1:
                    ax.set_xlabel("N (samples per pixel)", fontsize=8)
                if j == 0:
                    ax.set_ylabel("rel. MSE", fontsize=8)
        axes[0][0].legend(fontsize=6)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "environment_scenes.png"), dpi=80)
        plt.close(fig)

    if shadow:
        fig, ax = plt.subplots(figsize=(5, 3.5))
        for h in hdris:
            pts = sorted((int(r["nv"]), float(r["delta_e"])) for r in shadow if r["hdri"] == h and int(r["nv"]) > 0)
            base = [float(r["delta_e"]) for r in shadow if r["hdri"] == h and int(r["nv"]) == 0]
            line = ax.plot([p[0] for p in pts], [p[1] for p in pts], marker="o", label=h.replace("_1k.hdr", ""))
            if base:
                ax.axhline(base[0], color=line[0].get_color(), ls="--", lw=1)
        ax.set_xscale("log", base=2)
        ax.set_xlabel("N_v (shadow maps)")
        ax.set_ylabel("mean dE76 vs reference")
        ax.set_title("SH visibility (dashed: env_visibility none)", fontsize=9)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(os.path.join(out, "environment_scenes_sh.png"), dpi=80)
        plt.close(fig)

    lines = ["", "## Summary (computed by bench/plot_env_scenes.py from the CSV)", ""]
    if glossy:
        lines += ["![rel. MSE vs N](environment_scenes.png)", "",
                  "| scene | best at smallest N (HDRIs won) | best at largest N (HDRIs won) | median slope of log rel. MSE "
                  "vs log N per method |", "|---|---|---|---|"]
        for s in scenes:
            wins_lo, wins_hi = defaultdict(int), defaultdict(int)
            for h in hdris:
                per = {m: sorted(curves.get((s, h, m), [])) for m in METHODS}
                per = {m: p for m, p in per.items() if p}
                if not per:
                    continue
                wins_lo[min(per, key=lambda m: per[m][0][1])] += 1
                wins_hi[min(per, key=lambda m: per[m][-1][1])] += 1
            slopes = []
            for m in METHODS:
                v = median([slope([p[0] for p in curves[(s, h, m)]], [p[1] for p in curves[(s, h, m)]])
                            for h in hdris if curves.get((s, h, m))])
                if not math.isnan(v):
                    slopes.append(f"{m} {v:+.2f}")
            fmt = lambda w: ", ".join(f"{m} ({c})" for m, c in sorted(w.items(), key=lambda kv: -kv[1]))
            lines.append(f"| {s} | {fmt(wins_lo)} | {fmt(wins_hi)} | {'; '.join(slopes)} |")
    if shadow:
        lines += ["", "![SH visibility](environment_scenes_sh.png)", "",
                  "| HDRI | dE, no visibility | dE with SH visibility by N_v | best N_v |", "|---|---|---|---|"]
        for h in hdris:
            base = [float(r["delta_e"]) for r in shadow if r["hdri"] == h and int(r["nv"]) == 0]
            pts = sorted((int(r["nv"]), float(r["delta_e"])) for r in shadow if r["hdri"] == h and int(r["nv"]) > 0)
            if not pts:
                continue
            best = min(pts, key=lambda p: p[1])
            lines.append(f"| {h} | {base[0]:.3f} | " + ", ".join(f"{nv}: {e:.3f}" for nv, e in pts) +
                         f" | {best[0]}{' (worse than none)' if base and best[1] > base[0] else ''} |")
    with open(os.path.join(out, "environment_scenes.md"), "a") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
