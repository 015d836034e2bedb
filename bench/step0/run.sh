#!/bin/sh
# Step 0 at scale (issue 26; docs/rendering.md "Shadow maps at scale"): street scenes with N in
# {2, 8, 32, 128} car2 headlights and car bodies that cast shadows (bench/selection/street_gen.py
# --occluders, seed 1, 320 x 180, maps of 128^2), Step 0 with every instance's maps, with the
# culling, and with the culling and shadow_far_distance FAR (default 25 m); then the error of
# `render` at FAR and at 0 against `nearfield reference` on the N = 8 street.
#   bench/step0/run.sh [BUILD_DIR] [OUT_DIR]     (defaults: build, bench/results/step0)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build}
out=${2:-$here/../results/step0}
far=${FAR:-25}
mkdir -p "$out/scenes"
scenes=""
for n in ${INSTANCES:-2 8 32 128}; do
  f="$out/scenes/street_$n.json"
  python3 "$here/../selection/street_gen.py" --instances "$n" --seed 1 --occluders -o "$f"
  scenes="$scenes $f"
done
# shellcheck disable=SC2086
"$build/bench/bench_step0" --far "$far" --csv "$out/step0.csv" $scenes | tee "$out/step0.txt"
[ "${ERROR:-1}" = 0 ] && exit 0
s="$out/scenes/street_${ERROR_N:-8}.json"
"$build/nearfield" reference "$s" -o "$out/ref.exr" --spp "${REF_SPP:-256}"
"$build/nearfield" render "$s" -o "$out/exact.exr" --frames "${FRAMES:-16}" --stats "$out/exact.json"
"$build/nearfield" render "$s" -o "$out/far.exr" --frames "${FRAMES:-16}" --shadow-far-distance "$far" \
  --stats "$out/far.json"
"$build/nearfield" render "$s" -o "$out/allfar.exr" --frames "${FRAMES:-16}" --shadow-far-distance 0.001 \
  --stats "$out/allfar.json"
"$build/bench/bench_step0" --compare "$out/ref.exr" "$out/exact.exr" "$out/far.exr" "$out/allfar.exr" |
  tee "$out/error.txt"
