#!/usr/bin/env python3
"""Seeded street scenes for the light-selection bench (docs/sampling.md "Light selection").

    python3 bench/selection/street_gen.py --instances N [--seed S] [--layout scattered|aimed]
                                          [--width W --height H] [--spp K] [--occluders]
                                          [--shadow-map-size S] -o OUT.json

N headlight instances (car2 presets, two per car): `scattered` places N/2 cars at seeded
positions and headings on a 40 m x 14 m street (each pair lights its own patch); `aimed` repeats
the default scene's pair side by side along the kerb, every pair aimed at the same wall (the
issue's "car2 pair repeated"). Flat floor and a back wall, no occluders (visibility none), so the
bench times the luminaire sampling alone. With --occluders every car gets a body (a 1.8 x 1.4 x
4.2 m box behind its headlights) that casts shadows, and visibility is `shadowmaps`: the Step 0 at
scale bench (bench/step0/run.sh, docs/rendering.md "Shadow maps at scale"). Writes the scene JSON;
nothing else.
"""
import argparse
import json
import math
import random
import sys


def headlights(cx, cz, yaw_deg, name):
    """Two car2 headlights of a car at (cx, cz) heading yaw (degrees about +y; 0 = towards -z)."""
    yaw = math.radians(yaw_deg)
    out = []
    for side, dx in (("left", -0.65), ("right", 0.65)):
        # the car's local x axis after the yaw, then the luminaire's +z (emission) along the heading
        x = cx + dx * math.cos(yaw)
        z = cz - dx * math.sin(yaw)
        out.append({"name": f"{name} {side}", "preset": "car2", "intensity": 1.0,
                    "transform": {"translate": [round(x, 4), 0.7, round(z, 4)],
                                  "rotate": [0, round(180.0 + yaw_deg, 3), 0]}})
    return out


def body(cx, cz, yaw_deg, name):
    """The car's body: a box behind its headlights (their S planes stay outside it)."""
    yaw = math.radians(yaw_deg)
    fx, fz = -math.sin(yaw), -math.cos(yaw)  # the heading (the luminaires' +z)
    return {"name": f"{name} body", "type": "box", "size": [1.8, 1.4, 4.2], "material": "car",
            "transform": {"translate": [round(cx - 2.2 * fx, 4), 0.75, round(cz - 2.2 * fz, 4)],
                          "rotate": [0, round(yaw_deg, 3), 0]}}


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--instances", type=int, required=True, help="headlight instances (even, >= 2)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--layout", choices=["scattered", "aimed"], default="scattered")
    ap.add_argument("--width", type=int, default=320)
    ap.add_argument("--height", type=int, default=180)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--occluders", action="store_true", help="car bodies that cast shadows (visibility shadowmaps)")
    ap.add_argument("--shadow-map-size", type=int, default=128, help="with --occluders")
    ap.add_argument("-o", "--output", required=True)
    a = ap.parse_args(argv)
    if a.instances < 2 or a.instances % 2:
        ap.error(f"--instances must be even and >= 2, got {a.instances}")
    rng = random.Random(a.seed)
    lums, bodies = [], []
    cars = a.instances // 2
    for c in range(cars):
        if a.layout == "scattered":
            cx, cz = rng.uniform(-20.0, 20.0), rng.uniform(-6.0, 6.0)
            yaw = rng.uniform(0.0, 360.0)
        else:
            cx, cz, yaw = (c - (cars - 1) / 2.0) * 0.25, 0.0, 0.0
        lums += headlights(cx, cz, yaw, f"car{c + 1}")
        bodies.append(body(cx, cz, yaw, f"car{c + 1}"))
    scene = {
        "format": "nearfield-scene", "version": 1,
        "description": f"bench street: {a.instances} car2 headlights, layout {a.layout}, seed {a.seed} "
                       f"(bench/selection/street_gen.py)",
        "camera": {"position": [0.0, 14.0, 16.0], "target": [0.0, 0.0, -1.0], "up": [0, 1, 0],
                   "fov_y": 60, "resolution": [a.width, a.height]},
        "materials": {"asphalt": {"type": "lambert", "base_color": [0.35, 0.35, 0.35]},
                      "wall": {"type": "lambert", "base_color": [0.7, 0.7, 0.68]}},
        "objects": [
            {"name": "street", "type": "plane", "size": [60, 24], "material": "asphalt", "casts_shadows": False},
            {"name": "wall", "type": "plane", "size": [60, 6], "material": "wall", "casts_shadows": False,
             "transform": {"translate": [0, 3, -12], "rotate": [90, 0, 0]}},
        ],
        "luminaires": lums,
        "render": {"method": "ours", "sampler": "halton-scrambled", "spp": a.spp, "visibility": "none",
                   "tonemap": {"exposure": 0.35, "gamma": 2.2}},
    }
    if a.occluders:
        scene["materials"]["car"] = {"type": "lambert", "base_color": [0.2, 0.25, 0.4]}
        scene["objects"] += bodies
        scene["render"]["visibility"] = "shadowmaps"
        scene["render"]["shadow_map_size"] = a.shadow_map_size
        scene["description"] += ", car bodies cast shadows"
    with open(a.output, "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
