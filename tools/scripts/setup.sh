#!/usr/bin/env bash
# fovref set-up: installs the Debian 12 packages fovref needs (apt-get, as root or with sudo)
# and builds the default configuration (g++ -O2) into build/gcc-O2.
set -euo pipefail
cd "$(dirname "$0")/../.."

packages=(
  build-essential g++ clang cmake ninja-build pkg-config clang-format
  libglm-dev libstb-dev libtinyobjloader-dev libtinygltf-dev doctest-dev nlohmann-json3-dev libcli11-dev
  libopenexr-dev libssl-dev zlib1g-dev libembree-dev
  libegl-dev libopengl-dev libegl-mesa0 libvulkan-dev glslc mesa-vulkan-drivers gdb
  python3 python3-skimage chromium parallel librsvg2-bin assimp-utils
)
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  $sudo apt-get update
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${missing[@]}"
fi

cmake --preset release
cmake --build --preset release
echo "setup: built build/gcc-O2/fovref"
