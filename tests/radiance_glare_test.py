#!/usr/bin/env python3
"""Glare of nearfield's fisheye pictures against Radiance's rpict and evalglare (docs/glare.md,
"What is validated"; issue 32).

One room (6 x 4 m, 2.8 m high: floor, ceiling, four walls, grey Lambert), two ceiling panels of
4000 cd/m^2 on a 0.2 m square emitting down, an observer's eye 1.2 m high looking level along the
room, seen as a 180-degree angular fisheye (Radiance -vta -vh 180 -vv 180), SIZE x SIZE:

  * nearfield: the light-field `panel` preset (uniform Lambertian radiance, intensity 40: 4000
    cd/m^2), `render SCENE -o nf.hdr` (a Radiance picture with VIEW=, luminance-scaled). The
    panels' own appearance is in the picture (the camera rule of render/luminaire_view.h).
  * Radiance: each panel as an IES far field with its luminous opening, I(gamma) = L A cos(gamma)
    (= 160 cd at nadir), width = length = 0.2 m (LM-63 units type 2), written here; `ies2rad -u
    meters` turns the opening into an emitting polygon of radiance I / (A cos gamma) / 179 (its
    `flatcorr`), i.e. 4000 cd/m^2 seen from every direction, which `xform -rx -90 -t ...` puts at the
    panel's plane S (ies2rad aims it along -z; nearfield's `"rotate": [90, 0, 0]` along -y, as in
    radiance_render_test.py). The same room as polygons (`plastic`, no specular part), then
    `rpict -vta ... -ab 0`.

Why a light field on nearfield's side: `render` draws a scene's `farfield_lights` as point
sources, which light the room but do not appear in the picture (measured: the same IES file as a
far-field light gives UGR 0, no source above 2000 cd/m^2). The panel preset is the luminaire whose
far field through its opening is this IES file exactly (a uniform Lambertian square).

Inter-reflections: none on either side. nearfield `render` draws direct light only (no bounce,
docs/glare.md "An office"); rpict runs with -ab 0 and -av 0 0 0 (no ambient). Area sources: rpict
-ds 0.02 -dj 0 (the polygon subdivided for shadow rays), nearfield's light-field estimator; the lit
walls and floor only set the background luminance, whose error enters UGR as 8 log10 of a ratio.

Compared (UGR within 0.5, the issue's tolerance):
  1. evalglare on the nearfield picture against evalglare on the rpict picture (UGR);
  2. `nearfield glare` against evalglare on the same picture, each of the two: UGR; the same
     sources (count; each source's luminance and solid angle within 1e-3 and the same pixel count:
     both classify the same pixels with the same 2000 cd/m^2 threshold, and each pixel's solid
     angle comes from the same -vta formula); the veiling luminance, nearfield's CIE 140 L_v
     (`--road --lav 1`, a sum over source pixels) against evalglare's Lveil_cie, within 5 %
     (evalglare evaluates each source at its centre direction, nearfield per pixel);
  3. `nearfield glare --json` on both pictures: each source's luminance 4000 cd/m^2 within 2 %
     (RGBE rounding is 1/256), its solid angle within 2 pixels' solid angle (both tools classify
     a pixel by the ray through its centre, so only pixels cut by a square's edge can differ), the
     background luminance within 5 % and L_v within 5 %.
Where the two renders differ: the walls just below the ceiling, at grazing angles to the panels'
plane, are darker in nearfield (measured: 30-80 % of Radiance's in the top rows of the walls,
within 0.1 % elsewhere), because the panel preset's light field holds only the rays that cross
both its planes U and S within their extents (U's basis covers +-0.6 m fully, to +-0.8 m partly,
delta = 0.1 m: nothing beyond about 80-84 degrees from the normal), while ies2rad's polygon emits
to 90 degrees. That changes the background luminance by 1.4 %,
i.e. 0.05 UGR. rpict also renders the fisheye's square corners (directions beyond 90 degrees,
behind the observer); nearfield leaves them black. Neither evalglare nor `nearfield glare` uses
pixels outside the 180-degree circle.
The test can fail: the same rpict render with the opening stated 1.5 times as long (the same
intensity: 1/1.5 of the luminance on 1.5 times the solid angle, the kind of error a wrong
opening convention gives; closed form -1.41 UGR) must move evalglare's UGR by more than 0.5 with
both sources still found.

evalglare is run with -b 2000 (an absolute threshold of 2000 cd/m^2, nearfield glare's default)
and its view read from the picture's VIEW= line. Its background is the mean luminance of the
non-source pixels, nearfield's E_ind / pi (docs/glare.md): their difference is printed.

Exit 77 (skipped) without pyradiance (scripts/setup_python.sh).
"""
import argparse
import json
import math
import os
import pathlib
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from radiance_support import SKIP, radiance_bindir  # noqa: E402

SIZE = 256
L_PANEL = 4000.0  # cd/m^2
SIDE = 0.2  # m, the panel preset's square
EYE, LOOK = (0.0, 1.2, 2.0), (0.0, 1.2, 1.0)
PANELS = [(-0.8, 2.69, -0.5), (0.9, 2.69, 0.6)]  # plane S of each panel, 0.11 m below the ceiling
ALBEDO = {"floor": 0.3, "wall": 0.6, "ceiling": 0.8}
TOL_UGR = 0.5
TOL_LUM = 0.02
TOL_SAME = 1e-3
TOL_EDGE_PX = 2
TOL_LB = 0.05
TOL_LV = 0.05


def scene_json():
    return {
        "format": "nearfield-scene", "version": 1,
        "description": "radiance_glare_test: two light-field panels in a room, a fisheye eye",
        "camera": {"projection": "fisheye", "position": list(EYE), "target": list(LOOK), "up": [0, 1, 0],
                   "resolution": [SIZE, SIZE]},
        "materials": {k: {"type": "lambert", "base_color": [v] * 3} for k, v in ALBEDO.items()},
        "objects": [
            {"name": "floor", "type": "plane", "size": [4, 6], "material": "floor", "casts_shadows": False},
            {"name": "ceiling", "type": "plane", "size": [4, 6], "material": "ceiling", "casts_shadows": False,
             "transform": {"translate": [0, 2.8, 0], "rotate": [180, 0, 0]}},
            {"name": "front", "type": "plane", "size": [4, 2.8], "material": "wall", "casts_shadows": False,
             "transform": {"translate": [0, 1.4, -3], "rotate": [90, 0, 0]}},
            {"name": "back", "type": "plane", "size": [4, 2.8], "material": "wall", "casts_shadows": False,
             "transform": {"translate": [0, 1.4, 3], "rotate": [-90, 0, 0]}},
            {"name": "left", "type": "plane", "size": [2.8, 6], "material": "wall", "casts_shadows": False,
             "transform": {"translate": [-2, 1.4, 0], "rotate": [0, 0, -90]}},
            {"name": "right", "type": "plane", "size": [2.8, 6], "material": "wall", "casts_shadows": False,
             "transform": {"translate": [2, 1.4, 0], "rotate": [0, 0, 90]}},
        ],
        "luminaires": [{"name": f"panel {k}", "preset": "panel", "intensity": L_PANEL / 100.0,
                        "transform": {"translate": list(p), "rotate": [90, 0, 0]}} for k, p in enumerate(PANELS)],
        "render": {"visibility": "none"},
    }


def write_ies(path, side, length=None):
    """A Lambertian far field of the panel, I = L A cos(gamma) with A = SIDE^2 (the luminaire's
    true intensity), whose luminous opening is `side` wide and `length` (default `side`) long."""
    gammas = [5.0 * k for k in range(19)]  # 0..90
    cd = [L_PANEL * SIDE * SIDE * math.cos(math.radians(g)) for g in gammas]
    cd[-1] = 0.0
    path.write_text("\n".join([
        "IESNA:LM-63-2002", "[TEST] nearfield radiance_glare_test: a Lambertian square panel", "TILT=NONE",
        f"1 -1 1 {len(gammas)} 1 1 2 {side:g} {length or side:g} 0", "1 1 0",
        " ".join(f"{g:g}" for g in gammas), "0", " ".join(f"{v:.9g}" for v in cd)]) + "\n")


def radiance_room(lights):
    poly = lambda name, mod, pts: f"{mod} polygon {name}\n0\n0\n{3 * len(pts)} " + " ".join(
        f"{c:g}" for p in pts for c in p) + "\n"
    s = "".join(f"void plastic {k}_mat\n0\n0\n5 {v} {v} {v} 0 0\n" for k, v in ALBEDO.items())
    # normals into the room (Radiance: counterclockwise seen from the front)
    s += poly("floor", "floor_mat", [(-2, 0, -3), (-2, 0, 3), (2, 0, 3), (2, 0, -3)])
    s += poly("ceiling", "ceiling_mat", [(-2, 2.8, -3), (2, 2.8, -3), (2, 2.8, 3), (-2, 2.8, 3)])
    s += poly("front", "wall_mat", [(-2, 0, -3), (2, 0, -3), (2, 2.8, -3), (-2, 2.8, -3)])
    s += poly("back", "wall_mat", [(-2, 0, 3), (-2, 2.8, 3), (2, 2.8, 3), (2, 0, 3)])
    s += poly("left", "wall_mat", [(-2, 0, -3), (-2, 2.8, -3), (-2, 2.8, 3), (-2, 0, 3)])
    s += poly("right", "wall_mat", [(2, 0, -3), (2, 0, 3), (2, 2.8, 3), (2, 2.8, -3)])
    for k, p in enumerate(PANELS):
        s += f"!xform -n panel{k} -rx -90 -t {p[0]} {p[1]} {p[2]} {lights}\n"
    return s


def rpict(bindir, env, work, side, name, length=None):
    ies = work / f"{name}.ies"
    write_ies(ies, side, length)
    subprocess.run([str(bindir / "ies2rad"), "-u", "meters", "-c", "1", "1", "1", "-o", str(work / name), str(ies)],
                   check=True, env=env, cwd=work, stderr=subprocess.DEVNULL)
    (work / f"{name}_room.rad").write_text(radiance_room(work / f"{name}.rad"))
    octree = work / f"{name}.oct"
    with open(octree, "wb") as f:
        subprocess.run([str(bindir / "oconv"), str(work / f"{name}_room.rad")], check=True, env=env, cwd=work,
                       stdout=f)
    d = [LOOK[i] - EYE[i] for i in range(3)]
    out = work / f"{name}.hdr"
    with open(out, "wb") as f:
        subprocess.run([str(bindir / "rpict"), "-vta", "-vp", *map(str, EYE), "-vd", *map(str, d), "-vu", "0", "1", "0",
                        "-vh", "180", "-vv", "180", "-x", str(SIZE), "-y", str(SIZE), "-pa", "0", "-pj", "0",
                        "-ps", "1",
                        "-ab", "0", "-av", "0", "0", "0", "-ds", "0.02", "-dj", "0", "-dt", "0", "-dc", "1", "-lr", "1",
                        str(octree)], check=True, env=env, cwd=work, stdout=f)
    return out


def evalglare(bindir, env, hdr):
    """evalglare -d: ({label: value} of its result line "dgp,av_lum,...,ugr,...: v0 v1 ...", [per-source
    {label: value}] of its table "No pixels x-pos y-pos L_s Omega_s ...")."""
    r = subprocess.run([str(bindir / "evalglare"), "-b", "2000", "-d", str(hdr)], capture_output=True, text=True,
                       env=env)
    result, sources, header = None, [], None
    for line in r.stdout.splitlines():
        if ":" in line and "ugr" in line.split(":")[0].lower():
            labels, values = line.split(":", 1)
            result = dict(zip([l.strip().lower() for l in labels.split(",")], map(float, values.split())))
        elif " No pixels " in f" {line} ":
            header = [l.lower() for l in line.split()[3:]]  # after "N No pixels"
        elif header and line.split() and len(line.split()) >= len(header) + 2:
            v = line.split()
            sources.append(dict(zip(["no", "pixels"] + header, map(float, v))))
    if result is None:
        raise SystemExit(f"FAIL: unexpected evalglare output on {hdr}:\n{r.stdout}\n{r.stderr}")
    return result, sources


def nf_glare(binary, hdr):
    r = subprocess.run([binary, "glare", str(hdr), "--json", "--road", "--lav", "1"], capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"FAIL: nearfield glare {hdr}:\n{r.stderr}")
    return json.loads(r.stdout)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--nearfield", required=True)
    ap.add_argument("--shared", required=True, help="../shared/data (unused)")
    ap.add_argument("--keep", help="keep the work files in this folder")
    args = ap.parse_args()
    bindir = None
    for tool in ("ies2rad", "oconv", "rpict", "evalglare"):
        bindir = radiance_bindir(tool)
        if bindir is None:
            return SKIP
    t0 = time.time()
    tmp = tempfile.TemporaryDirectory()
    work = pathlib.Path(args.keep or tmp.name)
    work.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, RAYPATH=f"{work}{os.pathsep}{bindir.parent / 'lib'}",
               PATH=f"{bindir}{os.pathsep}{os.environ.get('PATH', '')}")  # oconv runs xform

    (work / "scene.json").write_text(json.dumps(scene_json(), indent=1))
    nf_hdr = work / "nf.hdr"
    r = subprocess.run([args.nearfield, "render", str(work / "scene.json"), "-o", str(nf_hdr)],
                       capture_output=True, text=True)
    if r.returncode != 0:
        print(f"FAIL: nearfield render:\n{r.stderr}")
        return 1
    rad_hdr = rpict(bindir, env, work, SIDE, "panel")
    wrong_hdr = rpict(bindir, env, work, SIDE, "long", 1.5 * SIDE)

    egd = {k: evalglare(bindir, env, h) for k, h in (("nearfield", nf_hdr), ("rpict", rad_hdr), ("long", wrong_hdr))}
    eg = {k: v[0] for k, v in egd.items()}
    ng = {k: nf_glare(args.nearfield, h) for k, h in (("nearfield", nf_hdr), ("rpict", rad_hdr))}
    failures = []

    def check(ok, msg):
        print(("ok    " if ok else "FAIL  ") + msg)
        if not ok:
            failures.append(msg)

    for k in ("nearfield", "rpict"):
        e, n = eg[k], ng[k]
        print(f"{k} picture: evalglare UGR {e['ugr']:.3f} (background {e['lum_backg']:.4g} cd/m2, sources "
              f"{e['lum_sources']:.5g} cd/m2 on {e['omega_sources']:.4g} sr, Lveil_cie {e['lveil_cie']:.4g} cd/m2); "
              f"nearfield glare UGR {n['ugr']:.3f} (background {n['background_luminance_cd_m2']:.4g} cd/m2, "
              f"L_v {n['road']['veiling_luminance_cd_m2']:.4g} cd/m2)")
        for s in n["sources"]:
            print(f"    nearfield glare source: L {s['luminance_cd_m2']:.5g} cd/m2, "
                  f"omega {s['solid_angle_sr']:.5g} sr, "
                  f"sigma {s['angle_from_line_of_sight_deg']:.2f} deg, p {s['position_index']:.3f}, {s['pixels']} px")
        for s in egd[k][1]:
            print(f"    evalglare source:       L {s['l_s']:.5g} cd/m2, omega {s['omega_s']:.5g} sr, "
                  f"sigma {s['sigma']:.2f} deg, p {s['posindx']:.3f}, {s['pixels']:.0f} px")
        check(abs(e["ugr"] - n["ugr"]) <= TOL_UGR,
              f"{k} picture: nearfield glare {n['ugr']:.3f} vs evalglare {e['ugr']:.3f} (tolerance {TOL_UGR})")
        # the same sources: luminance and solid angle of each, matched by direction
        srcs = egd[k][1]
        check(len(srcs) == len(n["sources"]), f"{k} picture: {len(n['sources'])} sources (nearfield glare), "
              f"{len(srcs)} (evalglare)")
        for s in n["sources"] if len(srcs) == len(n["sources"]) else []:
            t = max(srcs, key=lambda q: sum(x * y for x, y in zip(s["direction"], (q["xdir"], q["ydir"], q["zdir"]))))
            check(abs(s["luminance_cd_m2"] / t["l_s"] - 1) <= TOL_SAME and
                  abs(s["solid_angle_sr"] / t["omega_s"] - 1) <= TOL_SAME and s["pixels"] == t["pixels"],
                  f"{k} picture: source L {s['luminance_cd_m2']:.5g} / {t['l_s']:.5g} cd/m2, omega "
                  f"{s['solid_angle_sr']:.5g} / {t['omega_s']:.5g} sr (nearfield glare / evalglare)")
    check(abs(eg["nearfield"]["ugr"] - eg["rpict"]["ugr"]) <= TOL_UGR,
          f"evalglare: nearfield picture {eg['nearfield']['ugr']:.3f} vs rpict picture {eg['rpict']['ugr']:.3f}")
    check(abs(ng["nearfield"]["ugr"] - ng["rpict"]["ugr"]) <= TOL_UGR,
          f"nearfield glare: nearfield picture {ng['nearfield']['ugr']:.3f} vs rpict picture {ng['rpict']['ugr']:.3f}")

    a, b = ng["nearfield"]["sources"], ng["rpict"]["sources"]
    check(len(a) == len(PANELS) and len(b) == len(PANELS), f"sources found: {len(a)} (nearfield), {len(b)} (rpict), "
          f"{len(PANELS)} panels")
    if len(a) == len(b):
        for sa in a:
            sb = max(b, key=lambda s: sum(x * y for x, y in zip(s["direction"], sa["direction"])))
            check(abs(sa["luminance_cd_m2"] / L_PANEL - 1) <= TOL_LUM and abs(sb["luminance_cd_m2"] / L_PANEL - 1)
                  <= TOL_LUM, f"source luminance {sa['luminance_cd_m2']:.5g} / {sb['luminance_cd_m2']:.5g} cd/m2 "
                  f"(nearfield / rpict), {L_PANEL:g} within {TOL_LUM:.0%}")
            px = max(sa["solid_angle_sr"] / sa["pixels"], sb["solid_angle_sr"] / sb["pixels"])
            check(abs(sa["solid_angle_sr"] - sb["solid_angle_sr"]) <= TOL_EDGE_PX * px,
                  f"source solid angle {sa['solid_angle_sr']:.5g} / {sb['solid_angle_sr']:.5g} sr ({sa['pixels']} / "
                  f"{sb['pixels']} px) within {TOL_EDGE_PX} pixels")
    lb_n, lb_r = (ng[k]["background_luminance_cd_m2"] for k in ("nearfield", "rpict"))
    check(abs(lb_n / lb_r - 1) <= TOL_LB, f"background luminance {lb_n:.4g} / {lb_r:.4g} cd/m2 within {TOL_LB:.0%}")
    lv_n, lv_r = (ng[k]["road"]["veiling_luminance_cd_m2"] for k in ("nearfield", "rpict"))
    check(abs(lv_n / lv_r - 1) <= TOL_LV,
          f"veiling luminance (nearfield glare) {lv_n:.4g} / {lv_r:.4g} cd/m2 (nearfield / rpict picture) within "
          f"{TOL_LV:.0%}")
    for k in ("nearfield", "rpict"):
        lv, lv_eg = ng[k]["road"]["veiling_luminance_cd_m2"], eg[k]["lveil_cie"]
        check(abs(lv / lv_eg - 1) <= TOL_LV, f"{k} picture: veiling luminance nearfield glare {lv:.4g} vs "
              f"evalglare's Lveil_cie {lv_eg:.4g} cd/m2 within {TOL_LV:.0%}")

    gap = abs(eg["long"]["ugr"] - eg["rpict"]["ugr"])
    check(gap > TOL_UGR and len(egd["long"][1]) == len(PANELS),
          f"the opening stated 1.5 times as long moves evalglare's UGR by {gap:.2f} ({eg['long']['ugr']:.3f}, "
          f"{len(egd['long'][1])} sources; closed form 8 log10(1/1.5) = -1.41): the comparison can fail")
    print(f"time {time.time() - t0:.1f} s")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
