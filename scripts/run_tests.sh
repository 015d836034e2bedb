#!/usr/bin/env bash
# Installs what is missing, builds in build/ (or $NEARFIELD_BUILD_DIR) and runs the whole test
# suite through ctest. Window tests get a virtual display from Xvfb. Then the sanitizer step
# (docs/robustness.md): the loaders' tests (tests/sanitize/ci_tests.txt) under AddressSanitizer +
# UndefinedBehaviorSanitizer and a short fuzz run of every loader, both in build-fuzz/.
#   scripts/run_tests.sh              everything (what CI runs)
#   scripts/run_tests.sh ARGS...      only the normal suite, ARGS passed to ctest (e.g. -R Scene)
#   NEARFIELD_CI_SANITIZERS=0 scripts/run_tests.sh   the normal suite without the sanitizer steps
# Tests named *_Slow (exhaustive sweeps of combinations a default test already covers by one case
# each; docs/testing.md) run only with NEARFIELD_SLOW_TESTS=1 or when ARGS select tests themselves.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${NEARFIELD_BUILD_DIR:-$here/build}"
"$here/scripts/setup.sh"
venv="$("$here/scripts/setup_python.sh" | tail -1)"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DNEARFIELD_VENV="$venv"
cmake --build "$build" --parallel "$(nproc)"
slow=()
if [ $# -eq 0 ] && [ "${NEARFIELD_SLOW_TESTS:-0}" != 1 ]; then
  slow=(-E '_Slow$')
fi
(
  cd "$build"
  if [ -z "${DISPLAY:-}" ] && command -v xvfb-run >/dev/null; then
    exec xvfb-run -a -s "-screen 0 1280x1024x24" ctest --output-on-failure --parallel "$(nproc)" "${slow[@]}" "$@"
  fi
  exec ctest --output-on-failure --parallel "$(nproc)" "${slow[@]}" "$@"
)
if [ $# -gt 0 ] || [ "${NEARFIELD_CI_SANITIZERS:-1}" = 0 ]; then
  exit 0
fi
echo "run_tests: the loaders' tests under ASan + UBSan and a short fuzz run of every loader (build-fuzz/)"
"$here/scripts/run_fuzz.sh" "${NEARFIELD_FUZZ_SECONDS:-10}"
