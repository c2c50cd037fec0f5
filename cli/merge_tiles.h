#pragma once
// `orogen eval --tiles NxM --merge`: after every tile of a tiled build succeeded, the tiles of each height
// raster become one file under the name the untiled build gives it, equal to that build's file byte for byte.
// One rank streams it a band of rows at a time (the tiles of one tile row are open at once), so no rank ever
// holds the whole raster: the memory is a band of the world's width. The tiles and their side files are
// removed once the merged file is in place; a failure leaves the previous merged file (and the tiles) as
// they were.
//
// What merges:
// - WriteHeightfield in every format (EXR, TIFF, PNG16 and RAW16; the 16-bit ones need a fixed range, since
//   with 'auto' each tile maps its own range) and WriteImage in every format: the untiled build's bytes.
// - WritePoints and WriteCurves: one file joining the tiles' (cli/join_tiles.h); a value every tile computes
//   whole (a replicated river network) is in every tile's file alike and is written once.
// Every other writer (weight maps, control maps, meshes, scenes) keeps its tiles, named in a warning.
#include <functional>
#include <set>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/domain.h"
#include "graph/graph.h"
#include "graph/output_path.h"
#include "cli/tile_naming.h"

namespace orogen::cli {

// Why `graph` cannot be merged, checked before anything runs: each message names the node and what to change.
std::vector<std::string> merge_errors(const Graph& graph);

struct MergeResult {
  std::vector<std::string> files;      // the merged files written
  std::set<std::string> merged_nodes;  // the writers whose tiles were merged (and removed)
  std::vector<std::string> warnings;   // writers left as tiles, and why
};

// Merges the tiles of a build of every tile of `counts` over `full`, found by their names under `naming`;
// `starting(file)`, if given, is called before each merged file is written (progress of a long merge).
// Throws std::runtime_error (naming the file) if a tile is missing or does not fit, or a write fails.
MergeResult merge_tiles(const Graph& graph, const Domain& full, glm::ivec2 counts, TileNaming naming,
                        const OutputPolicy& policy, const std::function<void(const std::string&)>& starting = {});

}  // namespace orogen::cli
