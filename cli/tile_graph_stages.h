#pragma once
// The stages of a tiled or distributed build that run tile-graph nodes across the tiles, exact (graph/tile_graph.h,
// docs/distributed.md), before the tiles are evaluated.
//
// For each node of across_tile_nodes() in topological order, every rank:
//  1. evaluates the node's inputs on each of its tiles (earlier stages' results given, so nothing upstream of them
//     runs again) and starts the node's algorithm on exactly the tile's samples;
//  2. runs the algorithm's rounds: each tile's message goes to every rank in tile order (gather_by_tile), every
//     rank solves all tiles' messages the same way and keeps its own tiles' answers;
//  3. puts each tile's result together on the domain the tile's evaluation needs it on (the tile plus its
//     consumers' halos; the halo's samples come from the ranks that own the neighbouring tiles, through exchange),
//     without the outputs nobody links, and keeps it on disk: in the cache under the node's key for that tile (with
//     a --cache-dir) and in the build's spill (cli/tile_result_spill.h), not in memory.
// The inputs' evaluations keep in memory only what feeds a later stage; a later stage's inputs and the tiles'
// evaluations read the results they are given back from the spill, one tile at a time.
// A stage whose results every tile finds in the cache (a re-run with the same --cache-dir) is skipped (its results
// copied to the spill). The tile evaluations then get these results as given (EvalRequest::given_results) and
// report them cached.
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "cli/tile_result_spill.h"
#include "cli/tiling.h"
#include "evaluator/evaluator.h"
#include "graph/rank_group.h"

namespace orogen::cli {

struct TileGraphStages {
  const Graph* graph = nullptr;
  Domain domain;            // the whole domain
  glm::ivec2 counts{1, 1};  // tiles along x and y
  GlobalNodes global = GlobalNodes::Whole;
  std::set<std::string> across;   // across_tile_nodes(graph, domain, global)
  std::vector<glm::ivec2> tiles;  // this rank's tiles
  OutputPolicy output;            // as the evaluator's (cache keys of writers)
  const CancelToken* cancel = nullptr;
  bool quiet = false;  // rank 0 says what each stage did unless quiet
};

// A stage that could not finish: a node upstream failed on a tile, or the build was cancelled.
// `every_rank`: every rank throws it at the same point (an interruption agreed between two rounds), so the ranks can
// meet once more before they exit.
struct TileGraphStageError : std::runtime_error {
  bool cancelled = false;
  bool every_rank = false;
  TileGraphStageError(const std::string& what, bool was_cancelled, bool on_every_rank = false)
      : std::runtime_error(what), cancelled(was_cancelled), every_rank(on_every_rank) {}
};

// Puts the results of the across-tile nodes into `kept`, per tile of `stages.tiles` (by its index there) and node id.
// Collective: every rank calls it with its own tiles. Throws TileGraphStageError, and std::runtime_error when `kept`
// cannot write (a full disk).
void run_tile_graph_stages(const TileGraphStages& stages, Evaluator& evaluator, RankGroup& group,
                           TileResultSpill& kept);

}  // namespace orogen::cli
