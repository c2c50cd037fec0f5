#!/usr/bin/env bash
# Installs the Debian packages Orogen needs. Idempotent and non-interactive; run as root (it uses apt-get).
#   install-deps.sh             everything: the build, the editor, the tests, benchmarks, fuzzing, MPI, GDAL, Blender
#   install-deps.sh --programs  only what building and running orogen and orogen-editor needs (the quick start;
#                               Blender, Clang, MPI and the test tools are most of the download)
set -euo pipefail

programs=(
  build-essential cmake ninja-build pkg-config git ccache
  lld  # links in half the time of GNU ld (CMakeLists.txt: OROGEN_USE_LLD); it changes no object file
  libglm-dev
  libopenimageio-dev libopenexr-dev
  libcgal-dev libgmp-dev libmpfr-dev
  libopenmesh-dev
  libtinygltf-dev
  libtbb-dev
  nlohmann-json3-dev
  libcli11-dev
  libxxhash-dev libzstd-dev
  libhwy-dev
  libimgui-dev libglfw3-dev libgl-dev libgl1-mesa-dri libegl1 fonts-dejavu-core
)
rest=(
  openimageio-tools  # oiiotool makes the image fuzzer's seeds (tests/fuzz/make_image_seeds.sh)
  libgtest-dev libgmock-dev
  libbenchmark-dev
  libnoise-dev  # bench_noise compares with it
  xvfb xauth  # the editor's smoke test and screenshots
  gdal-bin  # gdalinfo, gdal_translate: the georeference and the tiles' VRT mosaics are checked (skipped without)
  blender  # tests/test_blender_import.cpp imports scenes headless (skipped without it)
  clang-14 libclang-rt-14-dev clang-format-14  # libFuzzer targets; the layout check
  libopenmpi-dev openmpi-bin  # distributed builds (docs/distributed.md)
)
case "${1:-}" in
  "") packages=("${programs[@]}" "${rest[@]}") ;;
  --programs) packages=("${programs[@]}") ;;
  *) echo "usage: install-deps.sh [--programs]" >&2; exit 2 ;;
esac

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
