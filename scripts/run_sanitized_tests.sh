#!/usr/bin/env bash
# The test suite under AddressSanitizer + UndefinedBehaviorSanitizer (NEARFIELD_SANITIZE=ON) in
# build-asan/ (or $NEARFIELD_ASAN_BUILD_DIR). Extra arguments go to ctest (e.g. -L / -R / -E to
# run a subset, as CI does: docs/robustness.md). Leaks inside the OpenCL and OpenGL drivers
# (PoCL, LLVM, Mesa) are suppressed by tests/sanitize/lsan.supp; none in nearfield's code are.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${NEARFIELD_ASAN_BUILD_DIR:-$here/build-asan}"
jobs="${NEARFIELD_JOBS:-$(nproc)}"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
# Debug with -O1: assertions stay on (RelWithDebInfo defines NDEBUG) and the ~300 sanitized
# translation units compile faster than at -O2; ASan's documentation recommends -O1.
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG=-O1 \
  -DCMAKE_C_FLAGS_DEBUG=-O1 -DNEARFIELD_SANITIZE=ON -DNEARFIELD_BUILD_BENCH=OFF "${launcher[@]}"
cmake --build "$build" --parallel "$jobs"
# The drivers unload modules at exit, leaving leaks LeakSanitizer cannot attribute: a preloaded
# dlclose that keeps them (tests/sanitize/no_dlclose.c) lets lsan.supp match them by library.
# verify_asan_link_order=0: the shim is preloaded ahead of the ASan runtime (it intercepts nothing
# ASan does). Slow unwinding (fast_unwind_on_malloc=0) would attribute them too, but makes every
# PoCL kernel compile minutes long. intercept_tls_get_addr=0: with dynamic TLS tracking on,
# LeakSanitizer's tracer reads a bogus dynamic TLS range of a driver module at exit and crashes
# ("Tracer caught signal 11", GCC 12 + glibc 2.36), failing tests at random.
"${CC:-cc}" -shared -fPIC -O2 -o "$build/no_dlclose.so" "$here/tests/sanitize/no_dlclose.c"
export LD_PRELOAD="$build/no_dlclose.so${LD_PRELOAD:+:$LD_PRELOAD}"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:halt_on_error=1:detect_odr_violation=0:verify_asan_link_order=0:intercept_tls_get_addr=0"
export LSAN_OPTIONS="suppressions=$here/tests/sanitize/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$here/tests/sanitize/ubsan.supp"
cd "$build"
if [ -z "${DISPLAY:-}" ] && command -v xvfb-run >/dev/null; then
  exec xvfb-run -a -s "-screen 0 1280x1024x24" ctest --output-on-failure --parallel "$jobs" "$@"
fi
exec ctest --output-on-failure --parallel "$jobs" "$@"
