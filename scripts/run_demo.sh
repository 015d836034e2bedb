#!/usr/bin/env bash
# Installs what is missing, builds, prints `nearfield info` and renders the built-in default
# scene (two generated car2 headlights; nothing downloaded) headless into out/ (or
# $NEARFIELD_OUT): default.exr (linear radiance, settings in the metadata), default.png
# (tone-mapped) and default_stats.json (per-step times, Fig. 10 breakdown, samples, memory),
# printing the timings. Also the GL -> OpenCL diagnostic pattern.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${NEARFIELD_BUILD_DIR:-$here/build}"
out="${NEARFIELD_OUT:-$here/out}"
"$here/scripts/setup.sh"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" --parallel "$(nproc)" --target nearfield
mkdir -p "$out"
"$build/nearfield" info
"$build/nearfield" pattern -o "$out"
echo
echo "== nearfield render scenes/default.json (640x360, K = 64) =="
"$build/nearfield" render "$here/scenes/default.json" --width 640 --height 360 --spp 64 \
  -o "$out/default.exr" --png "$out/default.png" --stats "$out/default_stats.json"
