#!/usr/bin/env bash
# Installs every Debian package Orogen's build, tests, benchmarks and editor need.
# Idempotent and non-interactive; run as root (it uses apt-get).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git ccache
  libglm-dev
  libopenimageio-dev openimageio-tools libopenexr-dev
  libcgal-dev libgmp-dev libmpfr-dev
  libopenmesh-dev
  libtinygltf-dev
  libtbb-dev
  nlohmann-json3-dev
  libcli11-dev
  libxxhash-dev libzstd-dev
  libgtest-dev libgmock-dev
  libbenchmark-dev
  libnoise-dev
  libhwy-dev
  libimgui-dev libglfw3-dev libgl-dev libgl1-mesa-dri libegl1 fonts-dejavu-core
  xvfb xauth
  gdal-bin  # gdalinfo, gdal_translate: the georeference and the tiles' VRT mosaics are checked (skipped without)
  blender  # tests/test_blender_import.cpp imports scenes headless (skipped without it)
  clang-14 libclang-rt-14-dev clang-format-14
  lld  # links the tests in half the time of GNU ld (CMakeLists.txt: OROGEN_USE_LLD)
  libopenmpi-dev openmpi-bin
)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install-deps.sh: run as root (or install sudo)" >&2; exit 1; fi
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps.sh: all ${#packages[@]} packages already installed"
  exit 0
fi
echo "install-deps.sh: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
