#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer (NEARFIELD_SANITIZE=ON) in
# build-asan/ (or $NEARFIELD_ASAN_BUILD_DIR). Leaks inside the OpenCL and OpenGL drivers (PoCL,
# LLVM, Mesa) are suppressed by tests/sanitize/lsan.supp; none in nearfield's code are.
#   scripts/run_sanitized_tests.sh --ci      builds only the executables of tests/sanitize/ci_tests.txt
#                                            and runs them (ctest -L sanitize-ci): what CI runs
#   scripts/run_sanitized_tests.sh [ARGS]    builds everything, runs ctest ARGS (default: the whole suite)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${NEARFIELD_ASAN_BUILD_DIR:-$here/build-asan}"
jobs="${NEARFIELD_JOBS:-$(nproc)}"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNEARFIELD_SANITIZE=ON \
  -DNEARFIELD_BUILD_BENCH=OFF "${launcher[@]}"
if [ "${1:-}" = "--ci" ]; then
  shift
  mapfile -t targets < <(grep -E '^[a-z]' "$here/tests/sanitize/ci_tests.txt")
  cmake --build "$build" --parallel "$jobs" --target "${targets[@]}"
  set -- -L sanitize-ci "$@"
else
  cmake --build "$build" --parallel "$jobs"
fi
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:halt_on_error=1:detect_odr_violation=0"
export LSAN_OPTIONS="suppressions=$here/tests/sanitize/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$here/tests/sanitize/ubsan.supp"
cd "$build"
if [ -z "${DISPLAY:-}" ] && command -v xvfb-run >/dev/null; then
  exec xvfb-run -a -s "-screen 0 1280x1024x24" ctest --output-on-failure --parallel "$jobs" "$@"
fi
exec ctest --output-on-failure --parallel "$jobs" "$@"
