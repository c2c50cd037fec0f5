#!/usr/bin/env bash
# The node SDK end to end, as a user meets it (issue 26): installs a Release build into a temporary prefix,
# builds examples/plugin out of tree against it, runs its tests (the testing kit, `orogen test-node` on the
# built library, a graph that uses it), and checks that the installed orogen lists the library's node and
# writes TIFF images through the image codec module installed with it.
#   scripts/test-plugin-sdk.sh [BUILD_DIR]    (default build/release, already built)
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build/release}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

cmake --install "$build" --prefix "$work/prefix" > /dev/null
cmake -S examples/plugin -B "$work/example" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$work/prefix" \
  > /dev/null
cmake --build "$work/example"
ctest --test-dir "$work/example" --output-on-failure
listing="$("$work/prefix/bin/orogen" --plugin "$work/example/libcanyon_nodes.so" nodes)"
grep -q "TerracedCanyon .*\[canyon_nodes\]" <<< "$listing" || {
  echo "the installed orogen does not list TerracedCanyon from canyon_nodes" >&2
  exit 1
}
OROGEN_PLUGIN_PATH="$work/example" "$work/prefix/bin/orogen" validate examples/plugin/canyon.json
OROGEN_PLUGIN_PATH="$work/example" "$work/prefix/bin/orogen" eval -q examples/plugin/canyon.json --resolution 65 \
  -o "$work/out"
test -s "$work/out/canyon.exr"
# TIFF files go through a module loaded on first use (PNG and EXR are written without it): the installed orogen
# loads the one installed beside it.
cat > "$work/tiff.json" << 'GRAPH'
{ "format": "orogen-graph", "version": 7, "domain": { "size": [100, 100], "resolution": [16, 16] },
  "nodes": [ { "id": "flat", "type": "Constant", "params": { "value": 5 } },
             { "id": "save", "type": "WriteHeightfield", "inputs": { "in": "flat.out" },
               "params": { "path": "flat.tif" } } ] }
GRAPH
loaded="$(LD_DEBUG=files "$work/prefix/bin/orogen" eval -q "$work/tiff.json" -o "$work/out" 2>&1 > /dev/null)"
grep -q "file=$work/prefix/[^ ]*/orogen_image_codec.so" <<< "$loaded" || {
  echo "the installed orogen did not load the image codec module of $work/prefix" >&2
  exit 1
}
test -s "$work/out/flat.tif"
echo "node SDK: example built against the installed SDK, tested and loaded"
