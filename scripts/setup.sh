#!/usr/bin/env bash
# Installs the Debian packages nearfield needs (docs/building.md). Idempotent.
set -euo pipefail
PKGS=(
  build-essential cmake ninja-build pkg-config git
  pocl-opencl-icd ocl-icd-opencl-dev opencl-headers opencl-clhpp-headers clinfo
  libglfw3-dev libepoxy-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri
  libfmt-dev libglm-dev libopenexr-dev libopenimageio-dev
  libtinygltf-dev nlohmann-json3-dev libimgui-dev libcli11-dev libembree-dev
  libgtest-dev libgmock-dev googletest libbenchmark-dev
  xvfb xauth python3-matplotlib python3-numpy python3-venv python3-pip
  clang-14 libclang-rt-14-dev
)
missing=()
for p in "${PKGS[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PKGS[@]} packages present"
  exit 0
fi
if [ "$(id -u)" -ne 0 ]; then
  echo "setup: missing packages: ${missing[*]}" >&2
  echo "setup: installing them needs root; run: sudo $0" >&2
  exit 1
fi
echo "setup: installing ${#missing[@]} packages: ${missing[*]}"
apt-get update
DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
echo "setup: done"
