#!/usr/bin/env bash
# Installs what is missing, builds, prints `nearfield info` and renders the built-in default
# output headless into out/ (or $NEARFIELD_OUT), printing timings.
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
