#pragma once
// Tiled builds (`orogen eval --tiles NxM [--tile I,J]`): the graph's domain cut into N x M tiles that share
// their border samples with their neighbours (tile (I, J) of a W-sample axis cut in N covers samples
// floor(I (W-1) / N) ... floor((I+1) (W-1) / N), both ends included), every tile written to its own files
// with the suffix `_xI_yJ`.
//
// Each node is evaluated on the tile expanded by the halo its consumers need, from the reach every node
// type declares (graph/node_type.h), clipped to the graph's domain: a writer sees exactly its tile, the
// node feeding it the tile plus that node's consumers' halos, and so on upstream. Point-wise and local
// nodes then reproduce, inside the tile, the full-domain result bit for bit, so neighbouring tiles agree on
// their shared borders and the tiles put together are the untiled build.
//
// Nodes whose result depends on the whole domain (reach global or undeclared; writers and
// domain-independent nodes excepted) are either evaluated on the whole domain and cut into the tiles
// (GlobalNodes::Whole: the tiles still join, and every tile's request has the same key for them, so the
// cache computes them once), or on their tile's part alone (GlobalNodes::PerTile: each tile needs only its
// own memory, but they do not join). Only rasters can be cut: a whole-domain node with no Heightfield or
// Image output (a mesh, curves, points) is evaluated per tile in both modes. seam_warnings() names them.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/domain.h"
#include "graph/graph.h"

namespace orogen::cli {

// "NxM": tile counts along x and y, each in [1, 4096]. nullopt and `error` set if malformed.
std::optional<glm::ivec2> parse_tile_counts(const std::string& text, std::string& error);
// "I,J": a tile's column and row (from 0), checked against `counts`. nullopt and `error` set if malformed
// or out of range.
std::optional<glm::ivec2> parse_tile_index(const std::string& text, glm::ivec2 counts, std::string& error);
// "X,Y": two finite numbers (for --origin and --size); `option` names the option in the error. With
// `positive`, both must be > 0.
std::optional<glm::dvec2> parse_number_pair(const std::string& text, const std::string& option, bool positive,
                                            std::string& error);

// Empty if a domain of `resolution` samples can be cut into `counts` tiles of at least 2 samples per axis
// (shared borders included), else why not.
std::string check_tile_counts(glm::ivec2 resolution, glm::ivec2 counts);

struct TileWindow {
  glm::ivec2 index{0, 0};  // (I, J)
  glm::ivec2 first{0, 0};  // first sample of the tile in the full domain
  glm::ivec2 size{1, 1};   // sample counts, shared borders included
};
// Tile `index` of a domain of `resolution` samples cut into `counts` tiles.
TileWindow tile_window(glm::ivec2 resolution, glm::ivec2 counts, glm::ivec2 index);

// "_x1_y0": the suffix of tile (1, 0)'s files.
std::string tile_suffix(glm::ivec2 index);
// `path` with `suffix` before its extension: "maps/height.exr" -> "maps/height_x1_y0.exr".
std::string with_suffix(const std::string& path, const std::string& suffix);
// Adds `suffix` to every output-file parameter of the graph's writers.
void add_output_suffix(Graph& graph, const std::string& suffix);

enum class GlobalNodes { Whole, PerTile };
// "whole" or "tile" (the --global-nodes option); nullopt otherwise.
std::optional<GlobalNodes> parse_global_nodes(const std::string& text);

// The nodes of `graph` that need the whole domain: a global or undeclared reach, not a writer, not
// domain-independent.
std::vector<std::string> whole_domain_nodes(const Graph& graph);

// The domain each node is evaluated on for tile `window` of `full` (EvalRequest::node_domains): the tile
// expanded by the halos downstream of the node plus the node's own halo, clipped to `full`; with
// GlobalNodes::Whole, `full` for the whole-domain nodes and everything upstream of them.
// Nodes in `across_tiles` run across the tiles (cli/tile_graph_stages.h): on the tile with their consumers' halos,
// like local nodes of no reach of their own.
std::map<std::string, Domain> tile_node_domains(const Graph& graph, const Domain& full, const TileWindow& window,
                                                GlobalNodes global = GlobalNodes::Whole,
                                                const std::set<std::string>& across_tiles = {});

// The whole-domain nodes of `graph` that a build of all its tiles runs across the tiles, exact, instead of on the
// whole domain (GlobalNodes::Whole only): tile-graph nodes whose type has an algorithm for their parameters
// (graph/tile_graph.h) and none of the inputs it refuses linked, whose outputs are all rasters (or curves and
// reports, the whole domain's on every tile), and that feed no node evaluated on the whole domain.
std::set<std::string> across_tile_nodes(const Graph& graph, const Domain& full, GlobalNodes global);

// What a tiled build of `graph` cannot make seamless or cheap, one message per node, naming it: the
// whole-domain nodes (PerTile: with the writers whose outputs then do not join; Whole: computed on the
// whole domain), and 16-bit heightfield writers whose height mapping follows each tile's own range.
std::vector<std::string> seam_warnings(const Graph& graph, GlobalNodes global,
                                       const std::set<std::string>& across_tiles = {});

}  // namespace orogen::cli
