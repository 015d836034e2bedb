#!/usr/bin/env bash
# Installs what is missing, builds in build/ (or $NEARFIELD_BUILD_DIR) and runs the whole test
# suite through ctest. Window tests get a virtual display from Xvfb.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${NEARFIELD_BUILD_DIR:-$here/build}"
"$here/scripts/setup.sh"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$build" --parallel "$(nproc)"
cd "$build"
if [ -z "${DISPLAY:-}" ] && command -v xvfb-run >/dev/null; then
  exec xvfb-run -a -s "-screen 0 1280x1024x24" ctest --output-on-failure --parallel "$(nproc)" "$@"
fi
exec ctest --output-on-failure --parallel "$(nproc)" "$@"
