#!/usr/bin/env python3
"""Test of bench/plot_report.py: its findings are computed from the data, not written as text.

Runs plot_report.py on tiny synthetic sweeps (one close-up target, `ours` and `uniform`, random
sampler) where the comparison goes one way, then the other way, then neither, and checks that
the report's sentences follow: which method needs fewer samples, whether `uniform` is faster
or slower for equal error, "equal within" for a tie, and the machine's ISA from meta.json.
A sentence hard-coded in plot_report.py cannot pass all three cases.

Then the 2 x 2 ablation (ours, uniform, ours-equal, uniform-equal on a `bike` close-up) in four
cases: balancing alone gains 4x, the restricted CDFs alone gain 4x, nothing gains, balancing
gains 2x; the "which factor carries the gain" sentence and the answer to "does `ours` need 4x
fewer samples than `uniform-equal` on the bike-like data" must follow each.

    bench/test_plot_report.py      (ctest: bench_report_findings, label bench)

Exit 77 (skipped) without matplotlib and numpy, which plot_report.py needs.
"""
import csv
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "plot_report.py")
COLUMNS = ("study,target,kind,luminaire,width,height,method,sampler,balance,search,search_depth,k_max,structure,"
           "K,frames,spp,reps,samples,samples_per_pixel,step0_ms,step1_ms,step2_ms,cl_other_ms,accumulate_ms,"
           "time_ms,time_median_ms,wall_ms,cpu_ms,samples_per_s,delta_e,delta_e_max,rel_mse,rel_bias,ref_key").split(",")
SPP = (16, 63, 252, 1008)


def point(method, spp, delta_e, time_ms, target="closeup-x", luminaire="x"):
    """One base-settings point of the spp study (the settings P.curve and P.point select)."""
    r = dict.fromkeys(COLUMNS, "0")
    r.update(study="spp", target=target, kind="closeup", luminaire=luminaire, width="16", height="16",
             method=method, sampler="random", balance="roulette", search="secant", search_depth="-1", k_max="0",
             structure="fused", K=str(spp), frames="1", spp=str(spp), reps="1", samples=str(256 * spp),
             samples_per_pixel=str(spp), step2_ms=str(time_ms), time_ms=str(time_ms), time_median_ms=str(time_ms),
             wall_ms=str(time_ms), cpu_ms=str(2 * time_ms), samples_per_s=str(256 * spp / time_ms * 1e3),
             delta_e=str(delta_e), delta_e_max=str(10 * delta_e), rel_mse=str(delta_e ** 2), rel_bias="0.001",
             ref_key="k")
    return r


def sweep(folder, uniform_error_factor):
    """ΔE ∝ spp^-1/2 for both methods, `uniform`'s × uniform_error_factor; time ∝ spp, equal per sample.
    So `uniform` needs factor² × the samples (and time) of `ours` for equal ΔE."""
    os.makedirs(folder)
    with open(os.path.join(folder, "points.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for spp in SPP:
            e = 4.0 / spp ** 0.5
            w.writerow(point("ours", spp, e, 0.1 * spp))
            w.writerow(point("uniform", spp, e * uniform_error_factor, 0.1 * spp))
    meta = {"mode": "full", "command": "synthetic", "load_start": "0.1 0.1 0.1", "load_end": "0.1 0.1 0.1",
            "machine": {"cpu_model": "Test CPU 9000", "cores": 2, "isa": "AVX2", "isa_flags": ["sse4_2", "avx", "avx2"],
                        "cl_device": {"name": "test-device", "type": "CPU", "platform": "Test CL"}},
            "targets": [{"name": "closeup-x", "kind": "closeup", "luminaire": "x", "width": 16, "height": 16,
                         "wall_distance_m": 1.0, "wall_half_size_m": 1.0, "box_pixels": 3.0, "box_cv": 0.5}]}
    with open(os.path.join(folder, "meta.json"), "w") as f:
        json.dump(meta, f)


def sweep_ablation(folder, factors):
    """The four ablation cells on closeup-bike (luminaire `bike`), random sampler: ΔE ∝ spp^-1/2
    times factors[method], so a cell needs factors[method]² × `ours`'s samples for equal ΔE."""
    os.makedirs(folder)
    with open(os.path.join(folder, "points.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for spp in SPP + (4032,):
            for m, k in factors.items():
                w.writerow(point(m, spp, k * 4.0 / spp ** 0.5, 0.1 * spp, "closeup-bike", "bike"))
    meta = {"mode": "full", "command": "synthetic", "load_start": "0.1 0.1 0.1", "load_end": "0.1 0.1 0.1",
            "machine": {"cpu_model": "Test CPU 9000", "cores": 2, "isa": "AVX2",
                        "cl_device": {"name": "test-device", "type": "CPU", "platform": "Test CL"}},
            "targets": [{"name": "closeup-bike", "kind": "closeup", "luminaire": "bike", "width": 16, "height": 16,
                         "wall_distance_m": 1.0, "wall_half_size_m": 1.0, "box_pixels": 3.0, "box_cv": 0.5}]}
    with open(os.path.join(folder, "meta.json"), "w") as f:
        json.dump(meta, f)


def report(folder, plots=False):
    """report.md of the sweep in folder (the plots only where asked: they take most of the time)."""
    subprocess.run([sys.executable, SCRIPT, folder] + ([] if plots else ["--no-plots"]), check=True,
                   stdout=subprocess.DEVNULL)
    with open(os.path.join(folder, "report.md")) as f:
        return f.read()


def luminaires_bullet(text):
    for line in text.splitlines():
        if line.startswith("- **Luminaires.**"):
            return line
    raise AssertionError("no Luminaires bullet in the report")


def main():
    try:
        import matplotlib  # noqa: F401
        import numpy  # noqa: F401
    except ImportError:
        print("test_plot_report: skipped: no matplotlib/numpy for", sys.executable)
        return 77
    failures, passed = [], []

    def check(cond, what):
        print(("ok   " if cond else "FAIL ") + what)
        (passed if cond else failures).append(what)

    with tempfile.TemporaryDirectory() as tmp:
        # uniform's ΔE is 2× ours at every spp: it needs 4× the samples, and (equal time per
        # sample) 4× the time: `ours` wins both ways.
        sweep(os.path.join(tmp, "ours_wins"), 2.0)
        text = report(os.path.join(tmp, "ours_wins"), plots=True)  # once with the plots: they must not fail
        b = luminaires_bullet(text)
        check("`ours` needs fewer samples on closeup-x (4×)" in b, "ours better: 'ours needs fewer samples' with 4×")
        check("`uniform` slower on closeup-x (4×)" in b, "ours better: 'uniform slower' with 4×")
        check("`uniform` needs fewer" not in b and "`uniform` faster" not in b, "ours better: no contrary words")
        check("- **ISA**: AVX2 (/proc/cpuinfo flags: sse4_2 avx avx2)" in text, "the ISA from meta.json is named")
        check("Test CPU 9000" in text and "test-device" in text, "the CPU and the OpenCL device are named")

        # The other way: uniform's ΔE is half of ours: it needs a quarter of the samples and time.
        sweep(os.path.join(tmp, "uniform_wins"), 0.5)
        b = luminaires_bullet(report(os.path.join(tmp, "uniform_wins")))
        check("`uniform` needs fewer samples on closeup-x (0.25×)" in b, "uniform better: the sentence flips")
        check("`uniform` faster on closeup-x (0.25×)" in b, "uniform better: 'uniform faster' with 0.25×")
        check("`ours` needs fewer" not in b and "`uniform` slower" not in b, "uniform better: no contrary words")
        check("pays off" not in b, "uniform better: no claim that importance sampling pays off")

        # A tie (1 % apart, within the stated ±5 %): "equal".
        sweep(os.path.join(tmp, "tie"), 1.01)
        b = luminaires_bullet(report(os.path.join(tmp, "tie")))
        check("equal within ±5 % on closeup-x" in b, "tie: 'equal within ±5 %'")
        check("gains nothing measurable" in b, "tie: the interpretation follows the verdict")

        # The 2 x 2 ablation. Error factors (ΔE / ours's ΔE at every spp) of each cell.
        def ablation(name, ue, u, oe):
            sweep_ablation(os.path.join(tmp, name), {"ours": 1.0, "uniform": u, "ours-equal": oe, "uniform-equal": ue})
            return report(os.path.join(tmp, name))

        # Balancing alone: equal counts double the error whatever the draw -> 4x the samples.
        text = ablation("balancing", 2.0, 1.0, 2.0)
        check("balancing carries the gain on closeup-bike (4× vs 1×)" in text, "ablation: balancing carries the gain")
        check("the restricted CDFs carry" not in text, "ablation balancing: no contrary words")
        check("(closeup-bike, random)? yes: 4× (paper 4×)" in text, "ablation balancing: the 4× question says yes")
        check("balancing saves 4× (4× with uniform draws, 4× with the restricted CDFs)" in text,
              "ablation balancing: the per-target sentence has both ratios")
        # The restricted CDFs alone: uniform draws double the error whatever the counts.
        text = ablation("cdfs", 2.0, 2.0, 1.0)
        check("the restricted CDFs carry the gain on closeup-bike (1× vs 4×)" in text, "ablation: the CDFs carry it")
        check("balancing carries" not in text, "ablation cdfs: no contrary words")
        check("(closeup-bike, random)? yes: 4×" in text, "ablation cdfs: the 4× question says yes")
        # Nothing: all four within 1 %.
        text = ablation("none", 1.01, 1.005, 1.005)
        check("neither factor gains samples on closeup-bike" in text, "ablation: neither factor")
        check("(closeup-bike, random)? no: 1.02×, both need equal samples within ±5 %" in text,
              "ablation none: the 4× question says no, equal")
        # Balancing gains 2x in samples only: the 4x claim is not reached.
        text = ablation("half", 2 ** 0.5, 1.0, 2 ** 0.5)
        check("(closeup-bike, random)? no: 2×, fewer than the paper's 4×" in text, "ablation 2×: not the paper's 4×")
        check("balancing carries the gain on closeup-bike (2× vs 1×)" in text, "ablation 2×: balancing carries it")
        # `uniform-equal` better than ours: the answer says so.
        text = ablation("reverse", 0.5, 1.0, 0.5)
        check("(closeup-bike, random)? no: 0.25×, `uniform-equal` needs fewer samples than `ours`" in text,
              "ablation reversed: uniform-equal needs fewer")
        check("neither factor gains samples on closeup-bike" in text, "ablation reversed: no factor gains")
    print(f"{len(passed)} passed, {len(failures)} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
