#!/usr/bin/env bash
# Installs the Debian 12 packages jaderender needs (only those missing; Slurm
# and munge for the cluster scripts and their test; Blender and numpy, which
# its glTF importer needs, for the Blender import's test; Node.js and npm,
# when there is no npm, for the glTF validator the tests run on preview.glb),
# installs that validator from the npm registry at the version
# tools/gltf-validator/package-lock.json pins, then configures and builds
# jaderender (Release) into build/. Safe to run again: with everything
# present it only rebuilds what changed.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  cmake ninja-build g++ pkg-config
  libembree-dev libopenimageio-dev openimageio-tools libopenexr-dev libglm-dev
  libtinygltf-dev libopenvdb-dev libboost-iostreams-dev libopencv-core-dev catch2
  libtbb-dev libtinyobjloader-dev nlohmann-json3-dev libstb-dev libcli11-dev
  fonts-dejavu-core
  slurm-wlm munge
  blender python3-numpy
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# Node.js may come from elsewhere than Debian (e.g. NodeSource, npm inside):
# Debian's packages only when there is no npm at all.
command -v npm >/dev/null 2>&1 || missing+=(nodejs npm)
if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup: installing ${missing[*]}" >&2
  sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q -o DPkg::Lock::Timeout=600 \
    "${missing[@]}" >/dev/null
fi

if [ ! -f tools/gltf-validator/node_modules/gltf-validator/package.json ]; then
  echo "setup: installing the glTF validator (npm ci in tools/gltf-validator)" >&2
  npm ci --prefix tools/gltf-validator --no-audit --no-fund --loglevel=error >/dev/null
fi

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build
