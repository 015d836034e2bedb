#!/usr/bin/env bash
# The frame on an NVIDIA GPU (issue 25; bench/results/gpu/README.md): the paper's frame (1024x768,
# K = 200, default scene: two car2 headlights, 2 x 143 shadow maps) first frame and progressive fps,
# and the moving camera at 1024x768, K = 16, per step as CSV (bench_frame, docs/rendering.md "Frame
# time per step"). Needs no network: run it from the repository root with the bundled binaries,
#   scripts/bundle_binary.sh gpu_bundle.tar.xz build/nearfield build/bench/bench_frame   (here)
#   OUT=/some/dir bench/gpu_frame.sh gpu_bundle.tar.xz                                      (there)
# or with a build folder holding nearfield and bench/bench_frame: bench/gpu_frame.sh build
# Writes into $OUT (default ./gpu_out): info.txt, paper_frame.csv, moving_1024.csv, viewer_320.csv,
# paper_frame.json/png (render --stats), run.log. About 1-2 minutes on an H100.
set -uo pipefail
src=${1:-gpu_bundle.tar.xz}
out=${OUT:-$PWD/gpu_out}
mkdir -p "$out"
log=$out/run.log
exec > >(tee -a "$log") 2>&1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

if [[ -f $src ]]; then  # a bundle: bin/ and lib/
  tar -xJf "$src" -C "$tmp"
  bin=$tmp/bin
  export LD_LIBRARY_PATH=$tmp/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
  bench=$bin/bench_frame
elif [[ -d $src ]]; then  # a build folder
  bin=$src
  bench=$src/bench/bench_frame
else
  echo "gpu_frame.sh: $src: neither a bundle nor a build folder" >&2
  exit 2
fi
nf=$bin/nearfield
[[ -x $nf && -x $bench ]] || { echo "gpu_frame.sh: nearfield or bench_frame missing under $src" >&2; exit 2; }

# NVIDIA's OpenCL and EGL without touching /etc: an ICD folder for the ICD loader and a vendor file
# for glvnd (the system's own are used when present).
mkdir -p "$tmp/icd"
cp /etc/OpenCL/vendors/*.icd "$tmp/icd/" 2>/dev/null  # keep the system's own ICDs visible
ls "$tmp/icd" | grep -qi nvidia || echo libnvidia-opencl.so.1 >"$tmp/icd/nvidia.icd"
export OCL_ICD_VENDORS=${OCL_ICD_VENDORS:-$tmp/icd}
if [[ -z ${__EGL_VENDOR_LIBRARY_FILENAMES:-} && ! -e /usr/share/glvnd/egl_vendor.d/10_nvidia.json ]]; then
  printf '{"file_format_version":"1.0.0","ICD":{"library_path":"libEGL_nvidia.so.0"}}\n' >"$tmp/10_nvidia.json"
  vendors=$tmp/10_nvidia.json  # first; the system's vendors (e.g. Mesa) after it
  for f in /usr/share/glvnd/egl_vendor.d/*.json; do [[ -e $f ]] && vendors+=:$f; done
  export __EGL_VENDOR_LIBRARY_FILENAMES=$vendors
fi
export NEARFIELD_CL_DEVICE=${NEARFIELD_CL_DEVICE:-gpu}

nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv >"$out/gpu.txt" 2>&1
"$nf" info >"$out/info.txt" 2>&1 || { cat "$out/info.txt"; echo "gpu_frame.sh: nearfield info failed" >&2; exit 1; }
grep -E 'selected|renderer' "$out/info.txt"

run() {  # name, then bench_frame's options
  local name=$1; shift
  echo "== $name"
  timeout 240 "$bench" --scene scenes/default.json --label "$name" --out "$out/$name.csv" "$@" ||
    echo "gpu_frame.sh: $name failed or timed out (rc $?)"
}
# The paper's frame: the first frame and 30 progressive frames (still camera).
run paper_frame --res 1024x768 --spp 200 --still 30 --moving 0
# A moving camera at 1024x768, K = 16 (every frame a new view: Step 0 and a restarted accumulation).
run moving_1024 --res 1024x768 --spp 16 --still 10 --moving 30
# The viewer's size, for comparison with the CPU table (docs/rendering.md).
run viewer_320 --res 320x180 --spp 16 --still 30 --moving 30

echo "== render (paper frame, one frame, stats + PNG)"
timeout 120 "$nf" render scenes/default.json --width 1024 --height 768 --spp 200 -o "$tmp/paper.exr" \
  --png "$out/paper_frame.png" --stats "$out/paper_frame.json" || echo "gpu_frame.sh: render failed (rc $?)"
cat "$out"/*.csv
