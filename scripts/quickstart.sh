#!/usr/bin/env bash
# Installs the dependencies, builds Orogen (Release) and evaluates the example terrain graph into out/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build/release -j"$(nproc)"
./build/release/cli/orogen eval graphs/terrain.json -o out --stats out/terrain-stats.json
echo "Outputs written to $(pwd)/out:"
ls -l out
