#!/usr/bin/env bash
# Packs built programs with the shared libraries they need (all but glibc and the C++ runtime, which
# the target has) and the GL dispatch libraries, so that they run on a machine where the project's
# dependencies are not installed, e.g. a GPU box without package access (bench/results/gpu/README.md).
#   scripts/bundle_binary.sh OUT.tar.xz build/nearfield [build/bench/bench_sampling ...]
# On the target: mkdir nf && tar -xJf OUT.tar.xz -C nf
#   LD_LIBRARY_PATH=$PWD/nf/lib nf/bin/nearfield info
# NVIDIA's OpenCL needs an ICD file naming its library (echo libnvidia-opencl.so.1 >
# /etc/OpenCL/vendors/nvidia.icd) and NVIDIA's EGL its vendor file in __EGL_VENDOR_LIBRARY_FILENAMES.
set -euo pipefail
[[ $# -ge 2 ]] || { echo "usage: $0 OUT.tar.xz PROGRAM [PROGRAM ...]" >&2; exit 2; }
out=$1; shift
stage=$(mktemp -d); trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/bin" "$stage/lib"
for prog in "$@"; do
  [[ -x $prog ]] || { echo "$0: $prog: not an executable" >&2; exit 1; }
  cp "$prog" "$stage/bin/"
  ldd "$prog" | awk '$3 ~ /^\// {print $3}' |
    grep -v -E '/(libc|libm|libpthread|libdl|librt|ld-linux[^/]*|libstdc\+\+|libgcc_s)\.so' |
    xargs -r -I{} cp -Ln {} "$stage/lib/"
done
for gl in libEGL.so.1 libGL.so.1 libGLX.so.0 libGLdispatch.so.0 libOpenGL.so.0; do
  f=$(ldconfig -p | awk -v n="$gl" '$1 == n && /x86-64/ {print $NF; exit}')
  [[ -n $f ]] && cp -L "$f" "$stage/lib/"
done
tmp="$out.tmp$$"
tar -C "$stage" -cf - bin lib | xz -9 -T0 >"$tmp" && mv "$tmp" "$out" || { rm -f "$tmp"; exit 1; }
echo "wrote $out ($(du -h "$out" | cut -f1)); $(ls "$stage/lib" | wc -l) libraries"
