#!/usr/bin/env bash
# Builds the libFuzzer harnesses (tests/fuzz) with clang-14 + ASan + UBSan in build-fuzz/ (or
# $NEARFIELD_FUZZ_BUILD_DIR), with the loaders' tests of tests/sanitize/ci_tests.txt under the same
# sanitizers; runs those tests (ctest label "sanitize-ci"), writes the seed corpus and fuzzes each
# loader for SECONDS (default 20, label "fuzz"). Findings (crash-*, leak-*, timeout-*) land in the
# build directory; the corpus grown so far is kept in build-fuzz/fuzz-corpus/ between runs.
# scripts/run_tests.sh runs this after the normal suite (docs/robustness.md).
# NEARFIELD_FUZZ_SEED (default 1) fixes libFuzzer's seed so a run repeats; 0 draws a random one.
#   scripts/run_fuzz.sh [SECONDS]       e.g. NEARFIELD_FUZZ_SEED=0 scripts/run_fuzz.sh 3600 for the long run (docs/robustness.md)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${NEARFIELD_FUZZ_BUILD_DIR:-$here/build-fuzz}"
seconds="${1:-20}"
jobs="${NEARFIELD_JOBS:-$(nproc)}"
command -v clang++-14 >/dev/null || { echo "run_fuzz.sh: clang++-14 is required (apt-get install clang-14 libclang-rt-14-dev)" >&2; exit 2; }
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DNEARFIELD_FUZZ=ON \
  -DNEARFIELD_BUILD_TESTS=OFF -DNEARFIELD_BUILD_BENCH=OFF -DNF_FUZZ_SECONDS="$seconds" \
  -DNF_FUZZ_SEED="${NEARFIELD_FUZZ_SEED:-1}" \
  -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_C_COMPILER=clang-14 "${launcher[@]}"
cmake --build "$build" --parallel "$jobs" --target fuzz_all sanitize_ci
cd "$build"
exec ctest -L 'sanitize-ci|fuzz' --output-on-failure --parallel "$jobs" --timeout $((seconds + 600))
