#!/bin/sh
# Light-selection bench (docs/sampling.md "Light selection"): street scenes with N in {2, 8, 32, 128}
# car2 headlights (seeded, bench/selection/street_gen.py), all vs flat with M picks (flat:M)
# at equal K, 320 x 180. MODES, REF_MODE, FRAMES, REF_FRAMES (even), WORST override.
#   bench/selection/run.sh [BUILD_DIR] [OUT_DIR]     (defaults: build, bench/results/selection)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build}
out=${2:-$here/../results/selection}
mkdir -p "$out/scenes"
scenes=""
for layout in ${LAYOUTS:-scattered aimed}; do
  for n in ${INSTANCES:-2 8 32 128}; do
    f="$out/scenes/street_${layout}_$n.json"
    python3 "$here/street_gen.py" --instances "$n" --seed 1 --layout "$layout" -o "$f"
    scenes="$scenes $f"
  done
done
# shellcheck disable=SC2086
"$build/bench/bench_selection" --spp 16 --frames "${FRAMES:-4}" --ref-frames "${REF_FRAMES:-48}" \
  --ref-mode "${REF_MODE:-flat:4}" --modes "${MODES:-flat:4,flat:1,all}" --worst "${WORST:-0}" \
  --csv "$out/selection.csv" $scenes | tee "$out/selection.txt"
