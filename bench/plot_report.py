#!/usr/bin/env python3
"""Plots and the Markdown report of a bench_sweep run (bench/README.md).

    bench/plot_report.py [RESULTS_DIR] [--no-plots]     (default: bench/results)

--no-plots writes report.md alone (bench/test_plot_report.py: the sentences, quickly).

Reads points.csv, references.csv, breakdown.csv, meta.json and, when present, micro.json
(Google Benchmark) from RESULTS_DIR and writes there:

    error_vs_spp.png    mean Lab ΔE76 vs samples per pixel, per target and method
    error_vs_time.png   mean Lab ΔE76 vs time per image (Steps 1-2 + accumulation), per target
    relmse_vs_spp.png   relative MSE (linear HDR) vs spp
    relmse_vs_time.png  relative MSE vs time per image
    breakdown.png       step breakdown: the scene's full frame (paper Fig. 10), close-ups' Steps 1-2
    studies.png         search depth (Fig. 5), samplers (Fig. 8), K_max (Fig. 9), balance (Eq. 12)
    report.md           machine, configuration, headline ratios, tables, the figures

Every ratio in the report comes from the points of this one run, and every sentence that compares
(which method needs fewer samples or less time, equal or not, which sampler's error is larger) is
built by the functions under "findings" from those numbers: the direction words follow the data,
"equal" means a ratio within EQUAL_TOL of 1 (bench/test_plot_report.py checks that the sentences
flip when the data do). Only matplotlib and numpy
(Debian python3-matplotlib, python3-numpy) are needed.
"""
import csv
import json
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

DPI = 72
METHOD_STYLE = {
    "ours": ("tab:blue", "o"),
    "paper": ("tab:purple", "v"),
    "uniform": ("tab:orange", "s"),
    "uniform-equal": ("tab:green", "D"),
    "ours-equal": ("tab:cyan", "P"),
    "global": ("tab:red", "^"),
}
# The 2 x 2 ablation (docs/sampling.md): (method, samples per image, draw inside B_m(p)).
CELLS = [
    ("ours", "balanced K_m", "restricted CDFs"),
    ("uniform", "balanced K_m", "uniform in box"),
    ("ours-equal", "equal K / M", "restricted CDFs"),
    ("uniform-equal", "equal K / M", "uniform in box"),
]
# The paper's spp for the bike (Figs. 11, 12) and car1 (Fig. 13).
PAPER_SPP = (63, 252, 1008, 63000)
SAMPLER_STYLE = {"halton": "-", "halton-scrambled": ":", "random": "--"}
PAPER = {
    "uniform_spp_ratio": "4× (252 vs 1008 spp, bike)",
    "uniform_err_ratio": "2.4× (3.4 vs 1.4 Lab, bike)",
    "global_spp_ratio": "~1000× (63 vs 63000 spp, bike)",
    "uniform_time_ratio": "1.7× (201 vs 118 ms, bike)",
    "search": "0.93 vs 0.89 Lab, same 83 ms (binary / secant = 1.04×)",
    "sampler": "Halton better at low spp (car1, Fig. 8)",
    "kmax": "0.63 mean / 23 max ΔE between the images; 13.5 vs 11.6 fps (bike, K = 200)",
    "bias": "not measured in the paper (docs/sampling.md: about −8 % on a test image)",
    "structure": "per-image passes only",
}


# ---------------------------------------------------------------------------------------------
# loading


def load_csv(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def fnum(v, default=float("nan")):
    try:
        return float(v)
    except (TypeError, ValueError):
        return default


class Points:
    """points.csv with numeric columns converted."""

    NUMERIC = {
        "width", "height", "search_depth", "k_max", "K", "frames", "spp", "reps", "samples",
        "samples_per_pixel", "step0_ms", "step1_ms", "step2_ms", "cl_other_ms", "accumulate_ms",
        "time_ms", "time_median_ms", "wall_ms", "cpu_ms", "samples_per_s", "delta_e", "delta_e_max", "rel_mse",
        "rel_bias",
    }

    def __init__(self, rows):
        self.rows = []
        for r in rows:
            d = dict(r)
            for k in self.NUMERIC:
                if k in d:
                    d[k] = fnum(d[k])
            self.rows.append(d)

    def select(self, **kw):
        out = []
        for r in self.rows:
            if all(r.get(k) == v for k, v in kw.items()):
                out.append(r)
        return out

    def targets(self):
        seen = []
        for r in self.rows:
            if r["target"] not in seen:
                seen.append(r["target"])
        return seen

    def curve(self, target, method, sampler="halton", study="spp", y="delta_e", x="spp"):
        """Sorted (x, y) of the base settings of a study (roulette, secant exact, fused, no K_max)."""
        pts = {}
        for r in self.select(study=study, target=target, method=method, sampler=sampler):
            if r["balance"] != "roulette" or r["search"] != "secant" or r["search_depth"] != -1:
                continue
            if r["structure"] != "fused" or r["k_max"] != 0:
                continue
            pts[r[x]] = r.get(y, float("nan"))
        xs = sorted(pts)
        return np.array(xs, dtype=float), np.array([pts[v] for v in xs], dtype=float)

    def point(self, target, method, spp, sampler="halton", study="spp"):
        for r in self.select(study=study, target=target, method=method, sampler=sampler):
            if r["spp"] == spp and r["structure"] == "fused" and r["k_max"] == 0 and r["search_depth"] == -1 \
                    and r["balance"] == "roulette":
                return r
        return None


# ---------------------------------------------------------------------------------------------
# interpolation on log-log curves


def spp_to_reach(spp, err, target):
    """Smallest spp at which the error curve reaches `target`, interpolated in log-log between the
    last point above and the first point at or below it on the curve's monotone lower envelope.
    Beyond the measured range: extrapolated with a power law fitted to the last three points.
    Returns (spp, how) with how in {"interpolated", "extrapolated", "measured", None}."""
    if len(spp) == 0 or not np.isfinite(target) or target <= 0:
        return float("nan"), None
    env = np.minimum.accumulate(err)
    below = np.nonzero(env <= target)[0]
    if len(below):
        i = below[0]
        if i == 0:
            if env[0] == target:
                return spp[0], "measured"
            # already below at the first point: extrapolate back with the first three points
            return powerlaw_solve(spp[:3], err[:3], target), "extrapolated"
        x0, x1 = math.log(spp[i - 1]), math.log(spp[i])
        y0, y1 = math.log(env[i - 1]), math.log(env[i])
        if y1 == y0:
            return spp[i], "interpolated"
        t = (math.log(target) - y0) / (y1 - y0)
        return math.exp(x0 + t * (x1 - x0)), "interpolated"
    return powerlaw_solve(spp[-3:], err[-3:], target), "extrapolated"


def powerlaw_solve(spp, err, target):
    ok = (np.asarray(spp) > 0) & (np.asarray(err) > 0)
    x, y = np.log(np.asarray(spp)[ok]), np.log(np.asarray(err)[ok])
    if len(x) < 2:
        return float("nan")
    b, a = np.polyfit(x, y, 1)
    if b >= 0:
        return float("nan")
    return math.exp((math.log(target) - a) / b)


def loglog_interp(xs, ys, x):
    """y(x) by linear interpolation in log-log (extrapolated linearly from the end segments)."""
    xs, ys = np.asarray(xs, dtype=float), np.asarray(ys, dtype=float)
    if len(xs) == 0 or not np.isfinite(x):
        return float("nan")
    if len(xs) == 1:
        return float(ys[0]) * x / float(xs[0])
    lx, ly = np.log(xs), np.log(ys)
    i = int(np.clip(np.searchsorted(lx, math.log(x)) - 1, 0, len(xs) - 2))
    t = (math.log(x) - lx[i]) / (lx[i + 1] - lx[i])
    return math.exp(ly[i] + t * (ly[i + 1] - ly[i]))


# ---------------------------------------------------------------------------------------------
# formatting


def fmt(v, digits=3):
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "–"
    if abs(v) >= 1000:
        return f"{v:,.0f}"
    return f"{v:.{digits}g}"


def ratio(a, b):
    if a is None or b is None or not (math.isfinite(a) and math.isfinite(b)) or b == 0:
        return float("nan")
    return a / b


def md_table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    for r in rows:
        out.append("| " + " | ".join(str(c) for c in r) + " |")
    return "\n".join(out)


def save(fig, path):
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


# ---------------------------------------------------------------------------------------------
# plots


def grid_for(n):
    cols = min(3, max(1, n))
    rows = (n + cols - 1) // cols
    return rows, cols


def plot_curves(P, path, y="delta_e", x="spp", ylabel="mean Lab ΔE76", xlabel="samples per pixel"):
    targets = P.targets()
    rows, cols = grid_for(len(targets))
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.3 * rows), squeeze=False)
    for ax in axes.flat[len(targets):]:
        ax.axis("off")
    for ax, t in zip(axes.flat, targets):
        for m, (color, marker) in METHOD_STYLE.items():
            for s, ls in SAMPLER_STYLE.items():
                if s == "halton-scrambled":
                    continue
                xs, ys = P.curve(t, m, s, y=y, x=x)
                ok = np.isfinite(xs) & np.isfinite(ys) & (xs > 0) & (ys > 0)
                if ok.sum() < 2:
                    continue
                ax.plot(xs[ok], ys[ok], ls, color=color, marker=marker, ms=3.5, lw=1.2,
                        label=f"{m} ({s})")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(t, fontsize=10)
        ax.grid(True, which="both", alpha=0.25)
        ax.set_xlabel(xlabel, fontsize=8)
        ax.set_ylabel(ylabel, fontsize=8)
        ax.tick_params(labelsize=7)
    handles, labels = [], []
    for ax in axes.flat:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in labels:
                handles.append(h)
                labels.append(lab)
    if handles:
        fig.legend(handles, labels, loc="lower center", ncol=min(4, len(labels)), fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.08 if rows > 1 else 0.14, 1, 1))
    save(fig, path)


def plot_breakdown(P, B, path):
    scene_rows = {}
    for r in B:
        key = (r["target"], r["structure"])
        scene_rows.setdefault(key, {}).setdefault(r["category"], []).append(fnum(r["ms"]))
    closeups = []
    for t in P.targets():
        for st in ("per-image", "fused"):
            rr = [x for x in P.select(study="structure", target=t, method="ours", structure=st) if x["spp"] == 252]
            if rr and rr[0]["kind"] == "closeup":
                closeups.append((t, st, rr[0]))
    panels = (1 if scene_rows else 0) + (1 if closeups else 0)
    if panels == 0:
        fig, ax = plt.subplots(figsize=(5, 2))
        ax.text(0.5, 0.5, "no breakdown in this run", ha="center", va="center")
        ax.axis("off")
        save(fig, path)
        return
    fig, axes = plt.subplots(1, panels, figsize=(6.2 * panels, 3.8), squeeze=False)
    ai = 0
    if scene_rows:
        ax = axes[0][ai]
        ai += 1
        cats = [("gbuffer", "G-buffer + readback"), ("shadow_maps", "shadow maps"),
                ("visibility", "visibility + upload"), ("surfaces_upload", "surface upload"),
                ("step1", "Step 1: A estimation"), ("step2", "Step 2: sampling+shading"),
                ("cl_other", "CL other"), ("accumulation", "accumulation"), ("step3", "Step 3: tone map")]
        labels = []
        bottoms = np.zeros(len(scene_rows))
        colors = plt.cm.tab10(np.linspace(0, 1, 10))
        for ci, (c, name) in enumerate(cats):
            vals = np.array([float(np.median(v.get(c, [0.0]))) for v in scene_rows.values()])
            ax.bar(range(len(scene_rows)), vals, bottom=bottoms, color=colors[ci % 10], label=name)
            bottoms += vals
        for (t, st) in scene_rows:
            labels.append(f"{t}\n{st}")
        ax.set_xticks(range(len(scene_rows)))
        ax.set_xticklabels(labels, fontsize=8)
        ax.set_ylabel("ms per frame (median of reps)", fontsize=8)
        spp = B[0]["spp"] if B else "?"
        ax.set_title(f"scene: full frame with Step 0, K = {spp}", fontsize=10)
        ax.legend(fontsize=7, loc="upper right")
        ax.tick_params(labelsize=7)
    if closeups:
        ax = axes[0][ai]
        cats = [("step1_ms", "Step 1: A estimation"), ("step2_ms", "Step 2: sampling+shading"),
                ("cl_other_ms", "CL other"), ("accumulate_ms", "readback+accumulation")]
        bottoms = np.zeros(len(closeups))
        colors = ["tab:green", "tab:blue", "tab:gray", "tab:olive"]
        for ci, (c, name) in enumerate(cats):
            vals = np.array([r[c] for (_, _, r) in closeups])
            ax.bar(range(len(closeups)), vals, bottom=bottoms, color=colors[ci], label=name)
            bottoms += vals
        ax.set_xticks(range(len(closeups)))
        ax.set_xticklabels([f"{t.replace('closeup-', '')}\n{st}" for (t, st, _) in closeups], fontsize=7)
        ax.set_ylabel("ms per image", fontsize=8)
        ax.set_title("close-ups: ours, 252 spp, per step", fontsize=10)
        ax.legend(fontsize=7)
        ax.tick_params(labelsize=7)
    fig.tight_layout()
    save(fig, path)


def style_legend(ax, styles, title=None):
    """A legend of line styles only (the colours name the targets in the figure legend)."""
    from matplotlib.lines import Line2D
    handles = [Line2D([0], [0], color="k", ls=ls, marker=mk, ms=3, lw=1) for _, ls, mk in styles]
    ax.legend(handles, [n for n, _, _ in styles], fontsize=7, title=title, title_fontsize=7, loc="best")


def plot_studies(P, path):
    from matplotlib.lines import Line2D
    targets = P.targets()
    colors = {t: plt.cm.tab10(i % 10) for i, t in enumerate(targets)}
    fig, axes = plt.subplots(2, 2, figsize=(10.5, 7.6))

    # Fig. 5: search kind and depth at K = 200
    ax = axes[0][0]
    for t in targets:
        for kind, ls in (("secant", "-"), ("binary", "--")):
            rows = [r for r in P.select(study="search", target=t, search=kind)]
            if not rows:
                continue
            rows.sort(key=lambda r: (r["search_depth"] < 0, r["search_depth"]))
            xs = [r["search_depth"] if r["search_depth"] >= 0 else 12 for r in rows]
            ax.plot(xs, [r["delta_e"] for r in rows], ls, marker="o", ms=3, color=colors[t])
    ax.set_title("Fig. 5: search depth at K = 200 (12 = exact)", fontsize=10)
    ax.set_xlabel("search depth (CDF evaluations per inversion)", fontsize=8)
    ax.set_ylabel("mean Lab ΔE76", fontsize=8)
    ax.set_yscale("log")
    style_legend(ax, [("secant", "-", "o"), ("binary", "--", "o")])

    # Fig. 8: samplers
    ax = axes[0][1]
    for t in targets:
        for smp, ls in SAMPLER_STYLE.items():
            xs, ys = P.curve(t, "ours", smp, study="sampler")
            if len(xs) < 2:
                continue
            ax.plot(xs, ys, ls, marker="o", ms=3, color=colors[t])
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_title("Fig. 8: samplers (ours)", fontsize=10)
    ax.set_xlabel("samples per pixel", fontsize=8)
    ax.set_ylabel("mean Lab ΔE76", fontsize=8)
    style_legend(ax, [(n, ls, "o") for n, ls in SAMPLER_STYLE.items()])

    # Fig. 9: K_max at K = 200
    ax = axes[1][0]
    ax2 = ax.twinx()
    for t in targets:
        rows = P.select(study="kmax", target=t)
        if not rows:
            continue
        rows.sort(key=lambda r: (r["k_max"] == 0, r["k_max"]))
        xs = [r["k_max"] if r["k_max"] > 0 else 200 for r in rows]
        ax.plot(xs, [r["delta_e"] for r in rows], "-", marker="o", ms=3, color=colors[t])
        base = rows[-1]["time_ms"] if rows[-1]["k_max"] == 0 else float("nan")
        ax2.plot(xs, [r["time_ms"] / base for r in rows], ":", marker="x", ms=3, color=colors[t])
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_title("Fig. 9: K_max at K = 200 (200 = no cap)", fontsize=10)
    ax.set_xlabel("K_max", fontsize=8)
    ax.set_ylabel("mean Lab ΔE76", fontsize=8)
    ax2.set_ylabel("time / time without cap", fontsize=8)
    ax2.tick_params(labelsize=7)
    style_legend(ax, [("ΔE (left)", "-", "o"), ("time (right)", ":", "x")])

    # Balance: bias of the total light vs spp
    ax = axes[1][1]
    for t in targets:
        for b, ls in (("paper", "-"), ("min1", "--"), ("roulette", ":")):
            rows = P.select(study="balance", target=t, balance=b)
            if not rows:
                continue
            rows.sort(key=lambda r: r["spp"])
            ax.plot([r["spp"] for r in rows], [100 * r["rel_bias"] for r in rows], ls, marker="o", ms=3,
                    color=colors[t])
    ax.axhline(0, color="k", lw=0.6)
    ax.set_xscale("log")
    ax.set_title("Eq. 12 balance: error of the total light (Halton)", fontsize=10)
    ax.set_xlabel("samples per pixel", fontsize=8)
    ax.set_ylabel("Σ Y / Σ Y(reference) − 1 (%)", fontsize=8)
    style_legend(ax, [("paper (round)", "-", "o"), ("min1", "--", "o"), ("roulette", ":", "o")])
    for a in axes.flat:
        a.tick_params(labelsize=7)
        a.grid(True, which="both", alpha=0.25)
    handles = [Line2D([0], [0], color=colors[t], lw=2) for t in targets]
    fig.legend(handles, targets, loc="lower center", ncol=len(targets), fontsize=8, frameon=False)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    save(fig, path)


# ---------------------------------------------------------------------------------------------
# headline ratios


def powerlaw_fit(xs, ys):
    """(a, b) of log y = a + b log x through the positive points (None when fewer than 2)."""
    xs, ys = np.asarray(xs, dtype=float), np.asarray(ys, dtype=float)
    ok = (xs > 0) & (ys > 0) & np.isfinite(xs) & np.isfinite(ys)
    if ok.sum() < 2:
        return None
    b, a = np.polyfit(np.log(xs[ok]), np.log(ys[ok]), 1)
    return a, b


def spp_ratio_fit(P, t, method, sampler, y="delta_e", spp=252.0):
    """spp at which `method`'s fitted power law reaches `ours`'s fitted value at `spp`, / spp."""
    fo = powerlaw_fit(*P.curve(t, "ours", sampler, y=y))
    fm = powerlaw_fit(*P.curve(t, method, sampler, y=y))
    if fo is None or fm is None or fm[1] >= 0:
        return float("nan")
    target = fo[0] + fo[1] * math.log(spp)
    return math.exp((target - fm[0]) / fm[1]) / spp


def headline(P, t, sampler):
    """The paper's comparisons on target t with `sampler` for ours/uniform (global: Halton)."""
    h = {"target": t, "sampler": sampler}
    ours = P.point(t, "ours", 252, sampler)
    if ours is None:
        return h
    e = ours["delta_e"]
    h["ours_252_de"] = e
    h["ours_252_ms"] = ours["time_ms"]
    # uniform (balanced K_m) and uniform-equal (K / M per image: the paper's Fig. 12 baseline)
    for method in ("uniform", "uniform-equal"):
        k = method.replace("-", "_")
        uni = P.point(t, method, 252, sampler)
        xs, ys = P.curve(t, method, sampler)
        if method != "uniform" and uni is None and not len(xs):
            continue
        if uni is not None:
            h[f"{k}_252_de"] = uni["delta_e"]
            h[f"{k}_err_ratio"] = ratio(uni["delta_e"], e)
            h[f"{k}_mse_ratio"] = ratio(uni["rel_mse"], ours["rel_mse"])
        spp_u, how_u = spp_to_reach(xs, ys, e)
        h[f"{k}_spp"], h[f"{k}_spp_how"] = spp_u, how_u
        h[f"{k}_spp_ratio"] = ratio(spp_u, 252.0)
        h[f"{k}_spp_ratio_fit"] = spp_ratio_fit(P, t, method, sampler)
        # time to reach ours@252's error: the method's time interpolated at the spp it needs
        xt, yt = P.curve(t, method, sampler, y="time_ms")
        t_u = loglog_interp(xt, yt, spp_u) if np.isfinite(spp_u) else float("nan")
        h[f"{k}_time_ms"] = t_u
        h[f"{k}_time_ratio"] = ratio(t_u, ours["time_ms"])
        xc, yc = P.curve(t, method, sampler, y="cpu_ms")
        ok = np.isfinite(yc) & (yc > 0)
        if ok.sum() >= 2 and np.isfinite(spp_u) and ours.get("cpu_ms", 0) > 0:
            h[f"{k}_cpu_ratio"] = ratio(loglog_interp(xc[ok], yc[ok], spp_u), ours["cpu_ms"])
    # global (Halton only): rel. MSE falls as 1/spp for an unbiased estimator, so its
    # extrapolation is sound; ΔE saturates at large errors (tone mapping), so its is not.
    xg, yg = P.curve(t, "global", "halton")
    if len(xg) and sampler == "halton":
        g = P.point(t, "global", 252, "halton")
        if g is not None:
            h["global_252_de"] = g["delta_e"]
            h["global_err_ratio"] = ratio(g["delta_e"], e)
        spp_g, how_g = spp_to_reach(xg, yg, e)
        h["global_spp_ratio"], h["global_spp_how"] = ratio(spp_g, 252.0), how_g
        xgm, ygm = P.curve(t, "global", "halton", y="rel_mse")
        spp_gm, how_gm = spp_to_reach(xgm, ygm, ours["rel_mse"])
        h["global_spp_ratio_mse"], h["global_spp_how_mse"] = ratio(spp_gm, 252.0), how_gm
        xgt, ygt = P.curve(t, "global", "halton", y="time_ms")
        t_g = loglog_interp(xgt, ygt, spp_gm) if np.isfinite(spp_gm) else float("nan")
        h["global_time_ratio_mse"] = ratio(t_g, ours["time_ms"])
        o63 = P.point(t, "ours", 63, "halton")
        g63k = P.point(t, "global", 63000, "halton")
        if o63 is not None and g63k is not None:
            h["fig11"] = (o63, g63k)
    return h


def study_search(P, t, depth=3):
    sec = [r for r in P.select(study="search", target=t, search="secant") if r["search_depth"] == depth]
    bin_ = [r for r in P.select(study="search", target=t, search="binary") if r["search_depth"] == depth]
    if not sec or not bin_:
        return None
    return sec[0], bin_[0]


def cpu_txt(a, b):
    """'; CPU ×r' for two points that both carry a process CPU time (load-robust), else ''."""
    ca, cb = a.get("cpu_ms", float("nan")), b.get("cpu_ms", float("nan"))
    if not (math.isfinite(ca) and math.isfinite(cb)) or cb <= 0:
        return ""
    return f" (CPU time ×{fmt(ca / cb)})"


def with_how(v, how):
    s = fmt(v)
    if how == "extrapolated":
        s += " (extrap.)"
    return s


# ---------------------------------------------------------------------------------------------
# findings: every sentence that compares is built here from the numbers, never written as text

# Two figures whose ratio is within this of 1 are reported as "equal" (a stated threshold, not a
# noise estimate: ΔE of a 128×128 close-up at 252 spp moves by a few per cent between seeds).
EQUAL_TOL = 0.05


def verdict(r, above, below, equal="equal", tol=EQUAL_TOL):
    """`above` when r > 1 + tol, `below` when r < 1 / (1 + tol), else `equal`; None if r is not finite."""
    if r is None or not math.isfinite(r):
        return None
    if r > 1.0 + tol:
        return above
    if r < 1.0 / (1.0 + tol):
        return below
    return equal


def span(vals, suffix="×"):
    """'lo-hi×' (or 'v×') of the finite values, '–' when none."""
    v = [x for x in vals if x is not None and math.isfinite(x)]
    if not v:
        return "–"
    lo, hi = min(v), max(v)
    return f"{fmt(lo)}{suffix}" if fmt(lo) == fmt(hi) else f"{fmt(lo)}-{fmt(hi)}{suffix}"


def grouped(items):
    """{word: [target (value×), ...]} → 'word on a (1.1×), b (1.2×); word2 on c (0.9×)'."""
    parts = [f"{w} on {', '.join(ts)}" for w, ts in items.items() if ts]
    return "; ".join(parts)


def machine_isa(m):
    """The CPU's ISA level from meta.json (bench_sweep records /proc/cpuinfo's flags), or what the
    OpenCL device string says PoCL compiled for when the run predates that field."""
    if m.get("isa"):
        flags = m.get("isa_flags") or []
        return f"{m['isa']} (/proc/cpuinfo flags{': ' + ' '.join(flags) if flags else ''})"
    cl = m.get("cl_device", {})
    hit = re.search(r"pthread-[\w.-]*?(skylake-avx512|avx512\w*|avx2|haswell|znver\d|icelake\w*|x86-64\S*)",
                    cl.get("version", "") + " " + cl.get("name", ""))
    if hit:
        return f"not recorded by this run; PoCL's kernel target: {hit.group(1)} (OpenCL device string)"
    return "not recorded by this run"


def time_spread(P):
    """Median and largest (median repetition / fastest repetition − 1) over repeated points."""
    s = sorted(r["time_median_ms"] / r["time_ms"] - 1.0 for r in P.rows
               if r.get("reps", 0) >= 2 and r.get("time_ms", 0) > 0 and math.isfinite(r.get("time_median_ms", float("nan"))))
    if not s:
        return None
    return float(np.median(s)), s[-1], len(s)


def curve_rises(ys, tol=EQUAL_TOL):
    """True when the error grows by more than tol from one spp to the next somewhere on the curve."""
    return any(b > a * (1.0 + tol) for a, b in zip(ys[:-1], ys[1:]) if math.isfinite(a) and math.isfinite(b))


def worst_bias(P, sampler):
    rows = [r for r in P.rows if r["sampler"] == sampler and r["method"] == "ours" and r["balance"] == "roulette"
            and r["k_max"] == 0 and r["search_depth"] == -1 and r["spp"] <= 252 and math.isfinite(r["rel_bias"])]
    return max(rows, key=lambda r: abs(r["rel_bias"])) if rows else None


def exact_from_depth(P, t, tol=EQUAL_TOL):
    """Smallest search depth from which both searches' ΔE stay within tol of their exact ΔE (depth −1)
    at every measured depth; None when the study is missing or never settles."""
    depths = None
    for kind in ("secant", "binary"):
        rows = P.select(study="search", target=t, search=kind)
        exact = [r["delta_e"] for r in rows if r["search_depth"] == -1]
        if not exact:
            return None
        off = {int(r["search_depth"]) for r in rows
               if r["search_depth"] >= 0 and abs(r["delta_e"] / exact[0] - 1.0) > tol}
        ds = sorted(int(r["search_depth"]) for r in rows if r["search_depth"] >= 0)
        if not ds:
            return None
        first = next((d for d in ds if all(e < d for e in off)), None)
        if first is None:
            return None
        depths = first if depths is None else max(depths, first)
    return depths


# ---------------------------------------------------------------------------------------------
# the 2 x 2 ablation: {equal, balanced} samples per image x {uniform in box, restricted CDFs}


def ablation(P, t, sampler):
    """Per cell of CELLS on target t: ΔE and rel. MSE at 252 spp, the spp / 252 each needs for
    `ours`'s ΔE (and rel. MSE) at 252 spp, and its time and CPU time at that spp / `ours`'s at 252.
    None when `ours` has no 252-spp point; cells without a curve are left out."""
    ours = P.point(t, "ours", 252, sampler)
    if ours is None:
        return None
    a = {"target": t, "sampler": sampler, "cells": {}}
    for m, _, _ in CELLS:
        xs, ys = P.curve(t, m, sampler)
        if not len(xs):
            continue
        pt = P.point(t, m, 252, sampler)
        c = {"de252": pt["delta_e"] if pt else float("nan"), "mse252": pt["rel_mse"] if pt else float("nan")}
        if m == "ours":  # the reference point of every ratio: 1 by definition
            spp_de, how_de, spp_mse, how_mse = 252.0, "measured", 252.0, "measured"
        else:
            spp_de, how_de = spp_to_reach(xs, ys, ours["delta_e"])
            spp_mse, how_mse = spp_to_reach(*P.curve(t, m, sampler, y="rel_mse"), ours["rel_mse"])
        c["spp_de"], c["how_de"] = ratio(spp_de, 252.0), how_de
        c["spp_mse"], c["how_mse"] = ratio(spp_mse, 252.0), how_mse
        xt, yt = P.curve(t, m, sampler, y="time_ms")
        c["time"] = ratio(loglog_interp(xt, yt, spp_de), ours["time_ms"]) if m != "ours" else 1.0
        xc, yc = P.curve(t, m, sampler, y="cpu_ms")
        ok = np.isfinite(yc) & (yc > 0)
        c["cpu"] = (ratio(loglog_interp(xc[ok], yc[ok], spp_de), ours.get("cpu_ms", float("nan")))
                    if m != "ours" and ok.sum() >= 1 else (1.0 if m == "ours" else float("nan")))
        a["cells"][m] = c
    return a


def factor_gains(a, key="spp_de"):
    """The two factors' gains from the cells' spp for equal error (> 1: the factor saves samples):
      balancing       equal -> balanced K_m: uniform-equal / uniform and ours-equal / ours
      restricted CDFs uniform -> restricted:  uniform-equal / ours-equal and uniform / ours
    each factor's gain is the geometric mean of its two ratios, so balancing × CDFs = total =
    uniform-equal / ours. None unless all four cells are there."""
    c = a["cells"]
    if not all(m in c and math.isfinite(c[m][key]) and c[m][key] > 0 for m, _, _ in CELLS):
        return None
    s = {m: c[m][key] for m, _, _ in CELLS}
    g = {
        "bal_uniform": s["uniform-equal"] / s["uniform"],
        "bal_restricted": s["ours-equal"] / s["ours"],
        "cdf_equal": s["uniform-equal"] / s["ours-equal"],
        "cdf_balanced": s["uniform"] / s["ours"],
        "total": s["uniform-equal"] / s["ours"],
    }
    g["balancing"] = math.sqrt(g["bal_uniform"] * g["bal_restricted"])
    g["cdfs"] = math.sqrt(g["cdf_equal"] * g["cdf_balanced"])
    return g


def carrier(g, tol=EQUAL_TOL):
    """Which factor carries the gain, from the two factors' gains (words follow the numbers)."""
    vb = verdict(g["balancing"], "helps", "hurts", "none")
    vc = verdict(g["cdfs"], "helps", "hurts", "none")
    if vb == "helps" and (vc != "helps" or g["balancing"] > g["cdfs"] * (1.0 + tol)):
        return "balancing carries the gain"
    if vc == "helps" and (vb != "helps" or g["cdfs"] > g["balancing"] * (1.0 + tol)):
        return "the restricted CDFs carry the gain"
    if vb == "helps" and vc == "helps":
        return "both factors share the gain about equally"
    return "neither factor gains samples"


def ablation_sentence(a, g):
    """One target's finding, every number and word from g."""
    def effect(x, s):
        """'saves 2×', 'costs 2× the samples' or 'changes nothing measurable, 1.02×' (s: verb suffix)."""
        return verdict(x, f"save{s} {fmt(x)}×", f"cost{s} {fmt(1 / x)}× the samples",
                       f"change{s} nothing measurable, {fmt(x)}×")

    tw = verdict(g["total"], f"{fmt(g['total'])}× fewer samples than", f"{fmt(1 / g['total'])}× more samples than",
                 "as many samples as")
    return (f"On {a['target']} ({a['sampler']}): `ours` needs {tw} `uniform-equal` for equal ΔE; "
            f"balancing {effect(g['balancing'], 's')} ({fmt(g['bal_uniform'])}× with uniform draws, "
            f"{fmt(g['bal_restricted'])}× with the restricted CDFs), the restricted CDFs {effect(g['cdfs'], '')} "
            f"({fmt(g['cdf_equal'])}× with equal counts, {fmt(g['cdf_balanced'])}× with balanced K_m): "
            f"{carrier(g)}.")


def bike_like(meta):
    """The close-up of the `bike` preset (the paper's bike layout), or None."""
    for t in meta.get("targets", []):
        if t.get("kind") == "closeup" and t.get("luminaire") == "bike":
            return t["name"]
    return None


def four_x(g, sampler, target):
    """Does `ours` need 4× fewer samples than `uniform-equal` (the paper's Fig. 12 claim)?"""
    r = g["total"]
    if r >= 4.0 / (1.0 + EQUAL_TOL):
        ans = f"yes: {fmt(r)}× (paper 4×)"
    elif r > 1.0 + EQUAL_TOL:
        ans = f"no: {fmt(r)}×, fewer than the paper's 4×, though `ours` still needs fewer samples"
    elif r >= 1.0 / (1.0 + EQUAL_TOL):
        ans = f"no: {fmt(r)}×, both need equal samples within ±{fmt(100 * EQUAL_TOL, 2)} %"
    else:
        ans = f"no: {fmt(r)}×, `uniform-equal` needs fewer samples than `ours`"
    return (f"Does `ours` need 4× fewer samples than the paper's baseline `uniform-equal` for equal ΔE on the "
            f"bike-like data ({target}, {sampler})? {ans}.")


def times_how(v, how):
    """'1.7×', or '1.7× (extrap.)' beyond the measured spp."""
    return fmt(v) + "×" + (" (extrap.)" if how == "extrapolated" else "")


def ablation_section(meta, P):
    L = ["## Ablation: which factor carries the gain", ""]
    L.append("Two choices separate `ours` from the paper's Fig. 12 baseline (`uniform-equal`): how many samples "
             "each image gets (equal K / M, or balanced K_m = K A_m(p) / A(p), Eq. 12) and how a sample is drawn "
             "in B_m(p) (uniformly, or through the restricted CDFs). The four methods are the four combinations "
             "(docs/sampling.md, \"The 2 x 2 ablation\"); `global` (Eq. 6) is in the headline section.")
    L.append("")
    L.append("*How to read*: per target and sampler, each row is one cell. 'spp / 252 for equal ΔE' is the spp the "
             "cell needs to reach `ours`'s ΔE at 252 spp, over 252 (1 for `ours`; 4 = four times the samples; "
             "*extrap.* = beyond the measured spp, power law through the last three points: far beyond them, "
             "e.g. hundreds of times, only an order of magnitude); the same for rel. MSE "
             "(linear HDR; falls as 1/spp for these unbiased estimators, so it extrapolates more soundly than ΔE, "
             "which saturates where the error is large). "
             "'time' and 'CPU time' are the cell's time at that spp over `ours`'s at 252 spp (CPU time is the "
             "process's, robust to the other users of the machine). The random sampler gives the estimators' own "
             "variance; Halton (the paper's) adds jitter from its shared sequence.")
    L.append("")
    findings, groups, fours = [], {}, []
    lum = bike_like(meta)
    any_table = False
    for t in P.targets():
        rows = []
        for sampler in ("random", "halton"):
            a = ablation(P, t, sampler)
            if a is None:
                continue
            for m, counts, draw in CELLS:
                c = a["cells"].get(m)
                if c is None:
                    continue
                rows.append([sampler, f"`{m}`", counts, draw, fmt(c["de252"]), fmt(c["mse252"]),
                             times_how(c["spp_de"], c["how_de"]), times_how(c["spp_mse"], c["how_mse"]),
                             fmt(c["time"]) + "×", fmt(c["cpu"]) + "×"])
            g = factor_gains(a)
            if g is not None:
                findings.append(ablation_sentence(a, g))
                if sampler == "random":
                    groups.setdefault(carrier(g), []).append(f"{t} ({fmt(g['balancing'])}× vs {fmt(g['cdfs'])}×)")
                if t == lum:
                    fours.append(four_x(g, sampler, t))
        if rows:
            any_table = True
            L.append(f"**{t}**")
            L.append("")
            L.append(md_table(["sampler", "method", "samples per image", "draw in B_m(p)", "ΔE @252", "rel. MSE @252",
                               "spp / 252 for equal ΔE", "spp / 252 for equal rel. MSE", "time for equal ΔE",
                               "CPU time for equal ΔE"], rows))
            L.append("")
    if not any_table:
        L.append("No ablation points in this run (`ours` at 252 spp is missing).")
        L.append("")
        return L
    L.append("### Findings (computed from the tables)")
    L.append("")
    L.append("*How to read*: a factor's gain is the geometric mean of its two ratios in the 2 × 2 (for balancing: "
             "`uniform-equal`/`uniform` and `ours-equal`/`ours`, in spp for equal ΔE), so balancing × restricted "
             "CDFs = `uniform-equal`/`ours`. A gain within ±"
             f"{fmt(100 * EQUAL_TOL, 2)} % of 1 counts as none; one factor 'carries the gain' when its gain exceeds "
             "the other's by more than that.")
    L.append("")
    if groups:
        L.append("**Summary (random sampler; balancing gain vs restricted-CDF gain)**: "
                 + "; ".join(f"{w} on {', '.join(ts)}" for w, ts in groups.items()) + ".")
        L.append("")
    for f in fours:
        L.append(f"**{f}**")
        L.append("")
    if lum is None:
        L.append("No close-up of the `bike` preset in this run: the 4× question is not answered here.")
        L.append("")
    for f in findings:
        L.append(f"- {f}")
    L.append("")
    return L


def paper_figures_section(meta, P, out):
    """Figs. 11, 12 (bike), 13 (car1), 9 (K_max) at the paper's spp, and Fig. 7 from visibility.csv."""
    L = ["## The paper's figures at the paper's spp", ""]
    lum = bike_like(meta)
    L.append("The luminaire closest to the paper's bike is the `bike` preset (host/luminaire/generator.cpp): "
             "9 × 7 images of 300² pixels, quadratic basis (`quadratic2`) of 15 mm support, Goesele's "
             "reconstruction, δ = 0.5 m — the layout of the paper's Table 1 — but its images are a synthetic smooth "
             "lens/beam emitter, not the measured filament and reflector. 1008 spp is run as 2 progressive frames "
             "of K = 504 (the sequences advance per frame: one estimate with 1008 samples per pixel; the CSV's K and "
             "frames columns say so), 63 000 as 63 frames of K = 1000. Halton, as in the paper, unless stated.")
    L.append("")
    rows = []
    if lum:
        for m, _, _ in CELLS + [("global", "", "")]:
            for sampler in ("halton", "random"):
                cells = []
                for spp in PAPER_SPP:
                    r = P.point(lum, m, spp, sampler, study="paper")
                    cells.append(f"{fmt(r['delta_e'])} / {fmt(r['time_ms'])} / {fmt(r['cpu_ms'])}" if r else "–")
                if any(c != "–" for c in cells):
                    rows.append([f"`{m}`", sampler] + cells)
    if rows:
        L.append(f"**Figs. 11 and 12 on {lum}**: ΔE / time ms / CPU ms per image")
        L.append("")
        L.append("*How to read*: one row per method and sampler, one column per spp of the paper. Paper Fig. 12: "
                 "`ours` 252 spp 1.4 Lab in 118 ms, uniform 252 spp 3.4 Lab in 84 ms, uniform 1008 spp 1.4 Lab in "
                 "201 ms; Fig. 11: `ours` 63 spp in 62 ms, global 63 000 spp in 4821 ms.")
        L.append("")
        L.append(md_table(["method", "sampler"] + [f"{s} spp" for s in PAPER_SPP], rows))
        L.append("")
        o252 = P.point(lum, "ours", 252, "halton", study="paper")
        u252 = P.point(lum, "uniform-equal", 252, "halton", study="paper")
        u1008 = P.point(lum, "uniform-equal", 1008, "halton", study="paper")
        if o252 and u252 and u1008:
            r1 = ratio(u252["delta_e"], o252["delta_e"])
            r2 = ratio(u1008["delta_e"], o252["delta_e"])
            w2 = verdict(r2, "still has a higher ΔE", "has a lower ΔE", "has about the same ΔE")
            L.append(f"Fig. 12 measured: at 252 spp `uniform-equal`'s ΔE is {fmt(r1)}× `ours`'s "
                     f"({fmt(u252['delta_e'])} vs {fmt(o252['delta_e'])}; paper 2.4×); at 1008 spp `uniform-equal` "
                     f"{w2} than `ours` at 252 ({fmt(u1008['delta_e'])} vs {fmt(o252['delta_e'])}, {fmt(r2)}×; "
                     f"paper: the same 1.4), in {fmt(ratio(u1008['time_ms'], o252['time_ms']))}× the time "
                     f"(CPU time {fmt(ratio(u1008['cpu_ms'], o252['cpu_ms']))}×; paper 201 vs 118 ms = 1.7×).")
            L.append("")
        o63 = P.point(lum, "ours", 63, "halton", study="paper")
        g63k = P.point(lum, "global", 63000, "halton", study="paper")
        if o63 and g63k:
            wd = verdict(ratio(g63k["delta_e"], o63["delta_e"]), "a lower", "a higher", "about the same")
            L.append(f"Fig. 11 measured: `ours` at 63 spp has {wd} ΔE than `global` at 63 000 spp "
                     f"({fmt(o63['delta_e'])} vs {fmt(g63k['delta_e'])}); `global` takes "
                     f"{fmt(ratio(g63k['time_ms'], o63['time_ms']))}× `ours`'s time (CPU time "
                     f"{fmt(ratio(g63k['cpu_ms'], o63['cpu_ms']))}×; paper 4821 vs 62 ms = 78×).")
            L.append("")
    c13 = [P.point(t, "ours", s, "halton", study="paper") for t in ("closeup-car1",) for s in (100, 200, 400)]
    if all(c13):
        L.append("**Fig. 13 on closeup-car1** (`ours`, Halton): ΔE "
                 + ", ".join(f"{fmt(r['delta_e'])} at {int(r['spp'])} spp ({fmt(r['time_ms'])} ms)" for r in c13)
                 + "; paper (close-up view) 1.12, 0.84, 0.53 at 100, 200, 400 spp (50, 84, 149 ms). "
                 f"ΔE falls {fmt(ratio(c13[0]['delta_e'], c13[2]['delta_e']))}× from 100 to 400 spp (paper 2.1×; "
                 "1/√spp would give 2×).")
        L.append("")
    if lum:
        k7 = [r for r in P.select(study="kmax", target=lum) if r["k_max"] == 7]
        k0 = [r for r in P.select(study="kmax", target=lum) if r["k_max"] == 0]
        if k7 and k0:
            a, b = k7[0], k0[0]
            L.append(f"**Fig. 9 on {lum}** (K = 200, K_max = 7 vs none, Halton): ΔE against the reference "
                     f"{fmt(a['delta_e'])} vs {fmt(b['delta_e'])} (max {fmt(a['delta_e_max'])} vs "
                     f"{fmt(b['delta_e_max'])}), {fmt(ratio(a['samples'], b['samples']))}× the samples in "
                     f"{fmt(ratio(a['time_ms'], b['time_ms']))}× the time{cpu_txt(a, b)}. The paper compares the two "
                     "images with each other (0.63 mean, 23 max ΔE; 13.5 vs 11.6 fps = 0.86× the time).")
            L.append("")
    vis = load_csv(os.path.join(out, "visibility.csv"))
    if vis:
        parts = []
        for t in dict.fromkeys(r["target"] for r in vis):
            none = [r for r in vis if r["target"] == t and r["visibility"] == "none"]
            sm = sorted((r for r in vis if r["target"] == t and r["visibility"] == "shadowmaps"),
                        key=lambda r: fnum(r["shadow_map_size"]))
            if none and sm:
                parts.append(f"{t}: ΔE {fmt(fnum(none[0]['delta_e']))} without visibility, "
                             f"{fmt(fnum(sm[0]['delta_e']))}-{fmt(fnum(sm[-1]['delta_e']))} with shadow maps of "
                             f"{sm[0]['shadow_map_size']}-{sm[-1]['shadow_map_size']}² (rel. bias "
                             f"{100 * fnum(none[0]['rel_bias']):+.1f} % vs {100 * fnum(sm[-1]['rel_bias']):+.1f} %)")
        L.append("**Fig. 7** (shadow-map visibility vs the ray-cast reference) is measured by `bench_visibility`, "
                 "not by this sweep: [visibility.md](visibility.md). From its table: " + "; ".join(parts) + ".")
        L.append("")
    return L


# ---------------------------------------------------------------------------------------------
# report


def gpu_line(cl):
    """Whether this run had a GPU (from the OpenCL device type), with the earlier H100 figures."""
    if "GPU" in str(cl.get("type", "")).upper():
        return f"this run's OpenCL device is a GPU ({cl.get('name', '?')})"
    return ("none in this run (no GPU was lent to the session that ran it; every time here is the CPU's). "
            "Earlier figures of the same kernels on an NVIDIA H100: [gpu/README.md](gpu/README.md)")


# The full plan's defaults (bench/sweep/plan.cpp), for the note on a reduced run.
FULL_DEFAULTS = {"closeup_res": 128, "closeup_max_spp": 4000, "closeup_ref_frames": 64, "scene": (320, 180), "scene_ref_frames": 16,
                 "studies": ("spp", "sampler", "kmax", "balance", "search", "structure", "paper")}


def reductions(meta, P):
    """What this full-mode run left out or shrank against the plan's defaults (from meta.json and
    the studies present), as a list of phrases; empty when nothing was reduced."""
    if meta.get("mode") != "full":
        return []
    out = []
    tg = meta.get("targets", [])
    res = sorted({t["width"] for t in tg if t.get("kind") == "closeup"})
    if res and res != [FULL_DEFAULTS["closeup_res"]]:
        out.append(f"close-ups at {'/'.join(str(r) for r in res)}² pixels (default {FULL_DEFAULTS['closeup_res']}²)")
    cf = meta.get("closeup_reference", {}).get("frames")
    if cf and cf != FULL_DEFAULTS["closeup_ref_frames"]:
        out.append(f"close-up references of {cf} frames of K = 1000 (default {FULL_DEFAULTS['closeup_ref_frames']})")
    sc = [(t["width"], t["height"]) for t in tg if t.get("kind") == "scene"]
    if sc and sc[0] != FULL_DEFAULTS["scene"]:
        out.append(f"the scene at {sc[0][0]}×{sc[0][1]} (default {FULL_DEFAULTS['scene'][0]}×{FULL_DEFAULTS['scene'][1]})")
    sf = meta.get("scene_reference", {}).get("frames")
    if sc and sf and sf != FULL_DEFAULTS["scene_ref_frames"]:
        out.append(f"a scene reference of {sf} frames (default {FULL_DEFAULTS['scene_ref_frames']})")
    top = max((r["spp"] for r in P.rows if r["study"] == "spp" and r["kind"] == "closeup"), default=None)
    if top is not None and top < FULL_DEFAULTS["closeup_max_spp"]:
        out.append(f"the spp study's close-ups up to {fmt(top)} spp (default {fmt(FULL_DEFAULTS['closeup_max_spp'])}; "
                   "`--max-spp`, beyond it the spp for equal error are extrapolated)")
    have = {r["study"] for r in P.rows}
    missing = [s for s in FULL_DEFAULTS["studies"] if s not in have]
    if missing:
        out.append("studies left out: " + ", ".join(missing))
    return out


def machine_block(meta):
    m = meta.get("machine", {})
    cl = m.get("cl_device", {})
    lines = [
        f"- **CPU**: {m.get('cpu_model', '?')} — {m.get('cores', '?')} logical cores (nproc), "
        f"{m.get('memory_gib', '?')} GiB RAM; {m.get('kernel', '')}",
        f"- **ISA**: {machine_isa(m)}",
        f"- **OpenCL device**: {cl.get('name', '?')} ({cl.get('type', '?')}, {cl.get('compute_units', '?')} "
        f"compute units, fp64 {'yes' if cl.get('fp64') else 'no'}) — {cl.get('version', '?')}; "
        f"driver {cl.get('driver_version', '?')}; platform {cl.get('platform', '?')} {cl.get('platform_version', '')}",
        f"- **GL renderer**: {m.get('gl_renderer') or 'not used in this run'}",
        f"- **GPU**: {gpu_line(cl)}",
        f"- **Build**: {m.get('build', '?')}; source commit `{m.get('git_commit', '?')}`",
        f"- **Date**: {m.get('date_utc', '?')} → {meta.get('date_end_utc', '?')} (UTC); sweep wall time "
        f"{fmt(meta.get('wall_s', float('nan')))} s",
        f"- **Load** (/proc/loadavg 1/5/15 min): {meta.get('load_start', '?')} at the start, "
        f"{meta.get('load_end', '?')} at the end",
    ]
    return "\n".join(lines)


def differences(meta, P, H):
    """The 'Where and why we differ from the paper' bullets: every comparison computed from this run."""
    bw = [t["box_pixels"] for t in meta.get("targets", []) if "box_pixels" in t]
    cv = [t["box_cv"] for t in meta.get("targets", []) if "box_cv" in t]
    box_range = (f"{fmt(min(bw), 2)}-{fmt(max(bw), 2)} pixels wide, luminance CV {fmt(min(cv), 2)}-{fmt(max(cv), 2)} "
                 "inside them" if bw and cv else "not measured in this run")
    out = []

    # luminaires: ours vs uniform, random sampler (the clean comparison)
    hs = [h for h in H.get("random", []) if "uniform_252_de" in h]
    lum = ("- **Luminaires.** Ours are synthetic (a virtual acquisition of smooth lens/beam emitters, "
           "docs/luminaire-format.md), not the measured bike/car data (sharp filament and reflector images); "
           f"their boxes B_m(p) are {box_range} (Setup table).")
    if hs:
        by_spp = {"`ours` needs fewer samples": [], "`uniform` needs fewer samples": [],
                  f"equal within ±{fmt(100 * EQUAL_TOL, 2)} %": []}
        keys = list(by_spp)
        for h in hs:
            r = h.get("uniform_spp_ratio")
            w = verdict(r, keys[0], keys[1], keys[2])
            if w:
                by_spp[w].append(f"{h['target']} ({fmt(r)}×)")
        n_equal, n_ours, n_uni = len(by_spp[keys[2]]), len(by_spp[keys[0]]), len(by_spp[keys[1]])
        lum += (" With the random sampler, the spp `uniform` needs to reach `ours`'s ΔE at 252 spp is "
                f"{span([h.get('uniform_spp_ratio') for h in hs])} of 252 (paper 4×) and the ΔE ratio at 252 spp "
                f"{span([h.get('uniform_err_ratio') for h in hs])} (paper 2.4×): {grouped(by_spp)}.")
        if n_equal and not n_ours and not n_uni:
            lum += (" Importance sampling *inside* a box gains nothing measurable over uniform sampling on these "
                    "luminaires; showing the paper's gain needs a luminaire with structure inside the boxes.")
        elif n_ours and not n_equal and not n_uni:
            lum += " Importance sampling inside the boxes pays off on every target, as in the paper."
        by_time = {"`uniform` faster": [], "`uniform` slower": [], f"equal within ±{fmt(100 * EQUAL_TOL, 2)} %": []}
        tk = list(by_time)
        for h in hs:
            r = h.get("uniform_time_ratio")
            w = verdict(r, tk[1], tk[0], tk[2])
            if w:
                by_time[w].append(f"{h['target']} ({fmt(r)}×)")
        if any(by_time.values()):
            lum += (" In time for equal ΔE (`uniform`'s time / `ours`'s; paper 1.7×): "
                    f"{grouped(by_time)}.")
    out.append(lum)

    out.append(
        "- **`uniform` keeps the balanced K_m** of Eq. 12 (docs/sampling.md: K_m as for `ours`, uniform on B_m(p)), "
        "so it isolates the restricted CDFs. The paper's uniform variant draws 'the same number of samples from "
        "each texture image' (no balancing), which also spends samples on dim images; its ratio includes that. "
        "`uniform-equal` is that baseline and `ours-equal` the fourth cell: the Ablation section separates the two.")

    # Halton vs random: monotonicity of the error curves and the bias of the total light
    targets = P.targets()
    rises = {}
    for s in ("halton", "random"):
        n = 0
        for t in targets:
            xs, ys = P.curve(t, "ours", s)
            n += 1 if len(xs) >= 2 and curve_rises(list(ys)) else 0
        rises[s] = n
    wh, wr = worst_bias(P, "halton"), worst_bias(P, "random")
    hal = ("- **Halton** (one sequence shared by all pixels, paper §6.3) gives image-wide structured error. "
           f"`ours`'s ΔE grows from one spp to the next by more than {fmt(100 * EQUAL_TOL, 2)} % somewhere on "
           f"{rises['halton']} of {len(targets)} targets with Halton and on {rises['random']} with the random sampler.")
    if wh and wr:
        rb = ratio(abs(wh["rel_bias"]), abs(wr["rel_bias"]))
        word = verdict(rb, "larger", "smaller", "about the same")
        hal += (f" The largest error of the total light (`ours`, up to 252 spp) is {100 * wh['rel_bias']:+.1f} % with "
                f"Halton ({wh['target']}, {int(wh['spp'])} spp) and {100 * wr['rel_bias']:+.1f} % with random "
                f"({wr['target']}, {int(wr['spp'])} spp): Halton's is {word} ({fmt(rb)}×).")
    hal += (" The random-sampler rows show the estimators' own variance; `halton-scrambled` rotates the sequence "
            "per pixel (Fig. 8 panel).")
    out.append(hal)

    # search depth
    ds = {t: exact_from_depth(P, t) for t in targets}
    ds = {t: d for t, d in ds.items() if d is not None}
    srch = "- **Search depth.**"
    if ds:
        groups = {}
        for t, d in ds.items():
            groups.setdefault(d, []).append(t)
        srch += (f" Both searches come within {fmt(100 * EQUAL_TOL, 2)} % of their exact ΔE (K = 200) from depth "
                 + "; ".join(f"{d} on for {', '.join(ts)}" for d, ts in sorted(groups.items()))
                 + " (the boxes are small, Setup table).")
    srch += (" Our depth counts CDF evaluations (a secant step evaluates two knots and counts 2, "
             "docs/sampling.md), so at depth 3 the secant gets 1-2 steps to the binary search's 3.")
    out.append(srch)

    m = meta.get("machine", {})
    cl = m.get("cl_device", {})
    out.append(
        f"- **Hardware.** {m.get('cores', '?')} logical cores of {m.get('cpu_model', '?')} (ISA: {machine_isa(m)}) "
        f"run the OpenCL kernels through {cl.get('platform', '?')} ({cl.get('type', '?')} device "
        f"{cl.get('name', '?')}) and GL through {m.get('gl_renderer') or 'no GL renderer'}, not a GTX 580: "
        "absolute times are not comparable with the paper's.")
    return out


def select_report(meta, P, R, B, micro):
    """The data report.md quotes, selected from the sweep's tables: no text is written here."""
    load = meta.get("load_start", "0").split()
    cores = meta.get("machine", {}).get("cores", 0) or 1
    targets = P.targets()
    D = {
        "mode": meta.get("mode", "?"),
        "shared": None,
        "reductions": reductions(meta, P),
        "setup_targets": meta.get("targets", []),
        "references": R,
        "targets": targets,
        "headline": {s_: [headline(P, t, s_) for t in targets] for s_ in ("random", "halton")},
    }
    if load and fnum(load[0], 0) > 0.5 * cores:
        D["shared"] = {"load": load[0], "cores": cores, "spread": time_spread(P)}
    # the other comparisons, one list per study, in the report's order
    D["search"] = [(t, sb) for t in targets for sb in [study_search(P, t, 3)] if sb]
    D["sampler"] = []
    for t in targets:
        pts = []
        for spp in (16, 32, 63):
            h = P.point(t, "ours", spp, "halton", study="sampler")
            r = P.point(t, "ours", spp, "random", study="sampler")
            if h and r:
                pts.append((spp, h, r))
        D["sampler"].append((t, pts))
    D["kmax"] = []
    for t in targets:
        k7 = [r for r in P.select(study="kmax", target=t) if r["k_max"] == 7]
        k0 = [r for r in P.select(study="kmax", target=t) if r["k_max"] == 0]
        if k7 and k0:
            D["kmax"].append((t, k7[0], k0[0]))
    D["bias"] = []
    for t in targets:
        rows_p = sorted([r for r in P.select(study="spp", target=t, method="paper", sampler="random")],
                        key=lambda r: r["spp"])
        if rows_p:
            p = rows_p[-1]
            o = P.point(t, "ours", int(p["spp"]), "random")
            if o:
                D["bias"].append((t, p, o))
    D["structure"] = []
    for t in targets:
        for spp in (252, 63):
            pi = [r for r in P.select(study="structure", target=t, method="ours", structure="per-image") if r["spp"] == spp]
            fu = [r for r in P.select(study="structure", target=t, method="ours", structure="fused") if r["spp"] == spp]
            if pi and fu:
                D["structure"].append((t, spp, pi[0], fu[0]))
                break
    # the breakdown: median ms per category of each (target, structure, K)
    agg = {}
    for r in B or []:
        agg.setdefault((r["target"], r["structure"], r["spp"]), {}).setdefault(r["category"], []).append(fnum(r["ms"]))
    D["breakdown"] = [(key, {c: float(np.median(v)) for c, v in cats.items()}, len(cats.get("wall", [])))
                      for key, cats in agg.items()]
    D["speed"] = [(t, m, r) for t in targets for m in ("ours", "paper", "uniform", "uniform-equal", "ours-equal", "global")
                  for r in [P.point(t, m, 252)] if r]
    D["micro"] = None
    if micro:
        benches = [b for b in micro.get("benchmarks", [])
                   if not (b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median")]
        D["micro"] = {"context": micro.get("context", {}), "benchmarks": benches}
    return D


def report_intro(meta, D):
    L = []
    L.append("# nearfield speed/accuracy sweep" +
             (" (quick mode: smoke test, not for quoting)" if D["mode"] == "quick" else ""))
    L.append("")
    L.append("Reproduces the comparisons of Lu et al. 2015 §7 on this project's synthetic luminaires "
             "(bench/README.md). Generated by `bench/run_sweep.sh` (bench/README.md explains every column and "
             "definition); every ratio below comes from the points of this one run.")
    L.append("")
    L.append(f"Command: `{meta.get('command', '?')}`")
    L.append("")
    L.append("## Machine")
    L.append("")
    L.append(machine_block(meta))
    sh = D["shared"]
    if sh:
        L.append("")
        spread = sh["spread"]
        noise = (f"over the {spread[2]} repeated points the median repetition took {fmt(100 * spread[0], 2)} % "
                 f"longer than the fastest (at most {fmt(100 * spread[1], 2)} %), a guide to the noise of "
                 "single-run times" if spread else "no point was repeated, so this run gives no noise estimate")
        L.append(f"> The machine was shared while this ran (load {sh['load']} on {sh['cores']} cores at the start, "
                 "more than half a core per core): times are the fastest of up to "
                 f"{meta.get('max_reps', '?')} repetitions for points under {fmt(meta.get('rep_budget_ms', 0))} ms, "
                 f"single runs above; {noise}. Errors do not depend on timing.")
    L.append("")
    if D["reductions"]:
        L.append("")
        L.append("> **Reduced run.** The full plan (about an hour or more on this 2-core machine, more when it is "
                 "shared) did not fit the time this run had, so it ran with " + "; ".join(D["reductions"]) +
                 " (the command line above). The errors of a smaller image "
                 "are of the same estimators; the studies left out keep their figures in earlier reports "
                 "(git history of this file).")
    L.append("")
    return L


def report_setup(D):
    L = ["## Setup", ""]
    rows = []
    for t in D["setup_targets"]:
        if t.get("kind") == "closeup":
            what = (f"Lambertian wall (albedo 0.8) at z = {t['wall_distance_m']:.2f} m, "
                    f"{2 * t['wall_half_size_m']:.2f} m square, luminaire frame; no Step 0, no visibility")
            extra = (f"{fmt(t.get('box_pixels', float('nan')))} px, CV {fmt(t.get('box_cv', float('nan')))}; "
                     f"precompute {fmt(t.get('precompute_ms', float('nan')))} ms")
        else:
            what = f"{os.path.basename(t.get('file', '?'))} through render::Renderer (headless EGL), shadow-map visibility"
            extra = ""
        rows.append([t["name"], t.get("luminaire", ""), f"{t['width']}×{t['height']}", what, extra])
    L.append(md_table(["target", "luminaire", "pixels", "what", "boxes B_m(p): width, CV of Y_m inside"], rows))
    L.append("")
    L.append("Box width = mean width of the boxes B_m(p) in image pixels; CV = std/mean of the image's luminance "
             "over the box, both weighted by A_m(p) over a 16×16 subset of the wall (`box_stats` in "
             "bench/sweep/closeup.h). Importance sampling by Y_m inside a box (`ours`) removes only the variance "
             "that comes from that variation, of relative size ~CV²; the rest (the basis function Φ_m across the "
             "box, the cosines, K_m's rounding) is the same for `uniform`.")
    L.append("")
    L.append("References (cached in `bench/results/cache/`, keyed by a hash of target and settings): "
             "method `ours`, sampler `random` (own seed), exact search, roulette balance, fused; "
             "their own noise is estimated from two halves of the frames.")
    L.append("")
    rows = []
    for r in D["references"]:
        rows.append([r["target"], fmt(fnum(r["spp"])), fmt(fnum(r["render_ms"]) / 1000.0) + " s",
                     "yes" if r["from_cache"] == "1" else "no", fmt(fnum(r["noise_rel_mse"])),
                     fmt(fnum(r["noise_delta_e"])), f"`{r['key']}`"])
    L.append(md_table(["target", "spp", "render time", "cached", "noise rel. MSE", "ΔE floor (≈)", "key"], rows))
    L.append("")
    L.append("Metrics: **ΔE** = mean CIE Lab ΔE76 over the scene-surface pixels after tone mapping both images "
             "with the reference's operator (the reference's mean luminance, the target's exposure and gamma: "
             "1 and 2.2 for the close-ups, the scene file's for the scene; display values decoded as sRGB "
             "before Lab); **rel. MSE** = Σ(x − r)² / Σ r² over those pixels and R, G, B "
             "(linear HDR); **bias** = Σ Y(x) / Σ Y(r) − 1. **time** = Steps 1-2 (OpenCL device time from "
             "profiling events) + host overhead of the sampler (clears, launches, waits) + readback and "
             "accumulation, per image, without Step 0; **CPU time** = the process's user + system CPU time over the "
             "same work (all PoCL threads; barely affected by other processes, unlike the device times); "
             "**samples/s** = samples drawn / Steps 1-2 device time.")
    L.append("")
    return L


def report_headline(D):
    H = D["headline"]
    L = []
    L.append("## Headline ratios")
    L.append("")
    L.append("Paper values are for its measured bike headlight on a GTX 580; ours are for the synthetic "
             "presets of docs/luminaire-format.md on this machine. 'spp for equal ΔE' = the spp at which the "
             "method's ΔE curve reaches `ours`'s ΔE at 252 spp: *interp.* on the curve's monotone lower envelope "
             "(log-log linear; *extrap.* = beyond the measured spp, power law through the last three points), "
             "*fit* between power laws fitted to both whole curves (robust to Halton's jitter). 'time for equal "
             "ΔE' = the method's time at that (interpolated) spp / `ours`'s time at 252 spp.")
    L.append("")
    for sampler in ("random", "halton"):
        hs = [h for h in H[sampler] if "ours_252_de" in h]
        if not hs:
            continue
        L.append(f"**`ours` vs `uniform`, sampler `{sampler}`**" + (
            " — independent samples per pixel: the estimators' own variance, the clean comparison"
            if sampler == "random" else " — the paper's sampler; its shared sequence makes the curves jitter"))
        L.append("")
        rows = []
        for h in hs:
            rows.append([
                h["target"], fmt(h.get("ours_252_de")), fmt(h.get("uniform_252_de")),
                fmt(h.get("uniform_err_ratio")) + "×",
                with_how(h.get("uniform_spp_ratio"), h.get("uniform_spp_how")) + "×",
                fmt(h.get("uniform_spp_ratio_fit")) + "×",
                fmt(h.get("uniform_mse_ratio")) + "×",
                fmt(h.get("uniform_time_ratio")) + "×",
                fmt(h.get("uniform_cpu_ratio")) + "×",
            ])
        L.append(md_table(["target", "ours ΔE @252", "uniform ΔE @252", "ΔE ratio @252 (paper 2.4×)",
                           "uniform spp / 252 for equal ΔE, interp. (paper 4×)", "same, fit",
                           "rel. MSE ratio @252", "uniform time / ours time for equal ΔE (paper 1.7×)",
                           "same, CPU time"], rows))
        L.append("")
    for sampler in ("random", "halton"):
        hs = [h for h in H[sampler] if "ours_252_de" in h and "uniform_equal_spp" in h]
        if not hs:
            continue
        L.append(f"**`ours` vs `uniform-equal`, sampler `{sampler}`** — the paper's Fig. 12 baseline: "
                 "K / M samples from every image (the remainder rotated per pixel), uniform on B_m(p)")
        L.append("")
        rows = []
        for h in hs:
            rows.append([
                h["target"], fmt(h.get("ours_252_de")), fmt(h.get("uniform_equal_252_de")),
                fmt(h.get("uniform_equal_err_ratio")) + "×",
                with_how(h.get("uniform_equal_spp_ratio"), h.get("uniform_equal_spp_how")) + "×",
                fmt(h.get("uniform_equal_spp_ratio_fit")) + "×",
                fmt(h.get("uniform_equal_mse_ratio")) + "×",
                fmt(h.get("uniform_equal_time_ratio")) + "×",
                fmt(h.get("uniform_equal_cpu_ratio")) + "×",
            ])
        L.append(md_table(["target", "ours ΔE @252", "uniform-equal ΔE @252", "ΔE ratio @252 (paper 2.4×)",
                           "uniform-equal spp / 252 for equal ΔE, interp. (paper 4×)", "same, fit",
                           "rel. MSE ratio @252", "uniform-equal time / ours time for equal ΔE (paper 1.7×)",
                           "same, CPU time"], rows))
        L.append("")
    hs = [h for h in H["halton"] if "global_252_de" in h]
    if hs:
        L.append("**`ours` vs `global`** (precomputed light importance sampling over whole images, Eq. 6; "
                 "Halton). rel. MSE falls as 1/spp for an unbiased estimator, so the spp `global` needs for "
                 "`ours`'s rel. MSE extrapolates soundly; ΔE saturates for large errors (the tone mapping "
                 "clips), so the ΔE-based figure is only indicative beyond the measured spp.")
        L.append("")
        rows = []
        for h in hs:
            rows.append([h["target"], fmt(h.get("global_252_de")), fmt(h.get("global_err_ratio")) + "×",
                         with_how(h.get("global_spp_ratio_mse"), h.get("global_spp_how_mse")) + "×",
                         fmt(h.get("global_time_ratio_mse")) + "×",
                         with_how(h.get("global_spp_ratio"), h.get("global_spp_how")) + "×"])
        L.append(md_table(["target", "global ΔE @252", "ΔE ratio @252",
                           "global spp / 252 for equal rel. MSE (paper ~1000× for equal quality)",
                           "global time / ours time for equal rel. MSE", "global spp / 252 for equal ΔE"], rows))
        L.append("")
        for h in hs:
            if "fig11" in h:
                o, g = h["fig11"]
                L.append(f"Paper Fig. 11 on {h['target']}: `ours` at 63 spp has ΔE {fmt(o['delta_e'])} in "
                         f"{fmt(o['time_ms'])} ms; `global` at 63 000 spp has ΔE {fmt(g['delta_e'])} in "
                         f"{fmt(g['time_ms'])} ms ({fmt(ratio(g['time_ms'], o['time_ms']))}× the time; "
                         f"rel. MSE {fmt(o['rel_mse'])} vs {fmt(g['rel_mse'])}): `ours` has the "
                         f"{'lower' if o['delta_e'] < g['delta_e'] else 'higher' if o['delta_e'] > g['delta_e'] else 'same'} "
                         f"ΔE in {'less' if o['time_ms'] < g['time_ms'] else 'more' if o['time_ms'] > g['time_ms'] else 'the same'} "
                         "time. Paper: 63 spp in 62 ms vs 63 000 spp in 4821 ms, `ours` visibly better.")
                L.append("")
    return L


def report_other(D):
    L = ["**Other comparisons** (Halton unless stated):", ""]
    rows = []
    for t, (s, b) in D["search"]:
        rows.append([t, "secant vs binary search, depth 3, K = 200 (Fig. 5)",
                     f"ΔE {fmt(s['delta_e'])} vs {fmt(b['delta_e'])} (binary/secant {fmt(ratio(b['delta_e'], s['delta_e']))}×); "
                     f"time {fmt(s['time_ms'])} vs {fmt(b['time_ms'])} ms" + cpu_txt(b, s), PAPER["search"]])
    for t, pts in D["sampler"]:
        parts = [f"{spp} spp: {fmt(h['delta_e'])} vs {fmt(r['delta_e'])} ({fmt(ratio(r['delta_e'], h['delta_e']))}×)"
                 for spp, h, r in pts]
        if parts:
            rows.append([t, "Halton vs random, ΔE (random/Halton), low spp (Fig. 8)", "; ".join(parts), PAPER["sampler"]])
    for t, a, b in D["kmax"]:
        rows.append([t, "K_max = 7 vs unbounded, K = 200 (Fig. 9)",
                     f"ΔE {fmt(a['delta_e'])} vs {fmt(b['delta_e'])} (max {fmt(a['delta_e_max'])} vs {fmt(b['delta_e_max'])}); "
                     f"samples ×{fmt(ratio(a['samples'], b['samples']))}; time ×{fmt(ratio(a['time_ms'], b['time_ms']))}"
                     + cpu_txt(a, b),
                     PAPER["kmax"]])
    for t, p, o in D["bias"]:
        rows.append([t, f"`paper` vs `ours` bias of the total light, random sampler, {int(p['spp'])} spp",
                     f"{100 * p['rel_bias']:+.2f} % vs {100 * o['rel_bias']:+.2f} %; ΔE {fmt(p['delta_e'])} vs {fmt(o['delta_e'])}",
                     PAPER["bias"]])
    for t, spp, a, b in D["structure"]:
        rows.append([t, f"per-image vs fused passes, ours, {spp} spp",
                     f"time {fmt(a['time_ms'])} vs {fmt(b['time_ms'])} ms (per-image/fused {fmt(ratio(a['time_ms'], b['time_ms']))}×)"
                     f"{cpu_txt(a, b)}; "
                     f"ΔE {fmt(a['delta_e'])} vs {fmt(b['delta_e'])}", PAPER["structure"]])
    L.append(md_table(["target", "comparison", "measured", "paper"], rows))
    L.append("")
    return L


def report_figures():
    L = ["## Figures", ""]
    for name, cap in (("error_vs_spp.png", "Mean Lab ΔE76 vs samples per pixel (solid: Halton, dashed: random)"),
                      ("error_vs_time.png", "Mean Lab ΔE76 vs time per image (Steps 1-2 + accumulation, no Step 0)"),
                      ("relmse_vs_spp.png", "Relative MSE (linear HDR) vs samples per pixel"),
                      ("relmse_vs_time.png", "Relative MSE (linear HDR) vs time per image"),
                      ("breakdown.png", "Step breakdown"),
                      ("studies.png", "Search depth, samplers, K_max, balance")):
        L.append(f"**{cap}**")
        L.append("")
        L.append(f"![{cap}]({name})")
        L.append("")
    return L


def report_breakdown(D):
    if not D["breakdown"]:
        return []
    L = ["## Step breakdown of a full frame (paper Fig. 10)", ""]
    for (t, st, spp), med, n_wall in D["breakdown"]:
        wall = med.get("wall", float("nan"))
        L.append(f"**{t}, {st}, K = {spp}**: frame {fmt(wall)} ms (median of {n_wall}), "
                 f"{fmt(med.get('samples', float('nan')))} samples")
        L.append("")
        rows = []
        for c, name in (("gbuffer", "Step 0: G-buffer + readback"), ("shadow_maps", "Step 0: shadow maps"),
                        ("visibility", "Step 0: visibility pass + readback + upload"),
                        ("luminaire_view", "Step 0: luminaire view"), ("surfaces_upload", "Step 0: surface upload"),
                        ("step1", "Step 1: A estimation"), ("step2", "Step 2: sampling + shading"),
                        ("cl_other", "CL other (clears, launches, waits)"),
                        ("accumulation", "readback + accumulation"), ("step3", "Step 3: GL tone mapping")):
            v = med.get(c, float("nan"))
            rows.append([name, fmt(v), fmt(100 * v / wall if wall else float("nan")) + " %"])
        L.append(md_table(["step", "ms", "share"], rows))
        L.append("")
        f10 = [("fig10_a_estimation", "Est. A", "3.8 %"), ("fig10_sampling_shading", "sampling + shading", "65.5 %"),
               ("fig10_shadow", "shadow", "9.2 %"), ("fig10_accumulation", "acc. buffer", "16.2 %"),
               ("fig10_other", "other", "5.3 %")]
        tot = sum(med.get(c, 0.0) for c, _, _ in f10)
        L.append("Paper Fig. 10 categories: " + "; ".join(
            f"{n} {fmt(100 * med.get(c, 0.0) / tot if tot else float('nan'))} % (paper {p})" for c, n, p in f10))
        L.append("")
    L.append("Our Step 2 kernels draw and shade each sample in one pass, so the paper's separate "
             "'sampling' (33.6 %) and 'shading' (31.9 %) are one number here; its per-image 'acc. buffer' "
             "is inside Step 2 too (our accumulation row is the progressive buffer). "
             "Step 0 has no GL/CL sharing on PoCL: readbacks and uploads are in it.")
    L.append("")
    return L


def report_speed(D):
    L = ["## Speed per method (252 spp, Halton)", ""]
    rows = []
    for t, m, r in D["speed"]:
        rows.append([t, m, fmt(r["step1_ms"]), fmt(r["step2_ms"]), fmt(r["cl_other_ms"]), fmt(r["accumulate_ms"]),
                     fmt(r["time_ms"]), fmt(r.get("cpu_ms", float("nan"))), fmt(r["samples_per_pixel"]),
                     fmt(r["samples_per_s"] / 1e6),
                     fmt(r["delta_e"]), fmt(r["rel_mse"]), f"{100 * r['rel_bias']:+.2f} %"])
    L.append(md_table(["target", "method", "Step 1 ms", "Step 2 ms", "CL other ms", "accum. ms", "time ms",
                       "CPU ms", "samples/pixel", "Msamples/s", "ΔE", "rel. MSE", "bias"], rows))
    L.append("")
    L.append("samples/pixel averages over all pixels (unlit ones draw none); K_m rounding and roulette make it "
             "differ from K. `global` draws K per pixel everywhere.")
    L.append("")
    return L


def report_micro(D):
    mi = D["micro"]
    if not mi:
        return []
    L = ["## Micro-benchmarks (`bench_micro`, Google Benchmark)", ""]
    ctx = mi["context"]
    L.append(f"{ctx.get('num_cpus', '?')} CPUs at {ctx.get('mhz_per_cpu', '?')} MHz, load "
             f"{', '.join(str(x) for x in ctx.get('load_avg', []))}; times are device time (manual timing from "
             "OpenCL profiling events) for the kernels, wall time for the precomputation.")
    L.append("")
    rows = []
    for b in mi["benchmarks"]:
        ips = b.get("items_per_second", float("nan"))
        name = re.sub(r"/(min_time:[0-9.]+|manual_time|real_time)", "", b.get("name", "?"))
        rows.append([name, fmt(b.get("real_time", float("nan"))) + " " + b.get("time_unit", ""),
                     fmt(ips / 1e6) + " M/s", b.get("label", "")])
    L.append(md_table(["benchmark", "time", "items/s", "items"], rows))
    L.append("")
    return L


def write_report(out, meta, P, R, B, micro):
    """report.md: select_report() picks the data, the report_* functions write the text."""
    D = select_report(meta, P, R, B, micro)
    L = report_intro(meta, D) + report_setup(D)
    # the 2 x 2 ablation and the paper's figures
    L.extend(ablation_section(meta, P))
    L.extend(paper_figures_section(meta, P, out))
    L += report_headline(D) + report_other(D) + report_figures() + report_breakdown(D) + report_speed(D)
    L += report_micro(D)
    # differences from the paper
    L.append("## Where and why we differ from the paper")
    L.append("")
    L.extend(differences(meta, P, D["headline"]))
    L.append("")
    with open(os.path.join(out, "report.md"), "w") as f:
        f.write("\n".join(L) + "\n")


def main():
    args = [a for a in sys.argv[1:] if a != "--no-plots"]
    plots = len(args) == len(sys.argv) - 1
    out = args[0] if args else os.path.join(os.path.dirname(os.path.abspath(__file__)), "results")
    with open(os.path.join(out, "meta.json")) as f:
        meta = json.load(f)
    P = Points(load_csv(os.path.join(out, "points.csv")))
    R = load_csv(os.path.join(out, "references.csv"))
    B = load_csv(os.path.join(out, "breakdown.csv"))
    micro = None
    mp = os.path.join(out, "micro.json")
    if os.path.exists(mp):
        try:
            with open(mp) as f:
                micro = json.load(f)
        except ValueError as e:
            print(f"plot_report: ignoring {mp}: {e}", file=sys.stderr)
    if not P.rows:
        sys.exit(f"plot_report: {out}/points.csv has no points")
    if not plots:
        write_report(out, meta, P, R, B, micro)
        print(f"plot_report: wrote report.md (no plots) in {out}")
        return
    plot_curves(P, os.path.join(out, "error_vs_spp.png"))
    plot_curves(P, os.path.join(out, "error_vs_time.png"), x="time_ms", xlabel="ms per image (Steps 1-2 + accum.)")
    plot_curves(P, os.path.join(out, "relmse_vs_spp.png"), y="rel_mse", ylabel="relative MSE (HDR)")
    plot_curves(P, os.path.join(out, "relmse_vs_time.png"), y="rel_mse", x="time_ms", ylabel="relative MSE (HDR)",
                xlabel="ms per image (Steps 1-2 + accum.)")
    plot_breakdown(P, B, os.path.join(out, "breakdown.png"))
    plot_studies(P, os.path.join(out, "studies.png"))
    write_report(out, meta, P, R, B, micro)
    print(f"plot_report: wrote report.md and 6 plots in {out}")


if __name__ == "__main__":
    main()
