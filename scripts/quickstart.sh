#!/usr/bin/env bash
# Installs the dependencies, builds what the main job needs (the orogen command and the editor, Release) and
# evaluates the example terrain graph into out/. scripts/test.sh builds the rest (tests, benchmarks).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh --programs
# Tests and benchmarks are configured, installed for and built by scripts/test.sh. A unity build (eight sources
# per compiler run) halves the compile time, most of which is parsing the same headers; the objects differ, the
# programs compute the same bytes. Developers who rebuild often configure with -DCMAKE_UNITY_BUILD=OFF.
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DOROGEN_TESTS=OFF -DOROGEN_BENCH=OFF \
  -DCMAKE_UNITY_BUILD=ON
cmake --build build/release -j"$(nproc)" --target orogen orogen-editor
./build/release/cli/orogen eval graphs/terrain.json -o out --stats out/terrain-stats.json
echo "Outputs written to $(pwd)/out:"
ls -l out
echo "The programs are build/release/cli/orogen and build/release/editor/orogen-editor;"
echo "'cmake --install build/release' copies both to /usr/local/bin (on the PATH)."
