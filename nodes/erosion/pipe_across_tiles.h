#pragma once
// PipeErosion across the tiles of a tiled or distributed build, exact (graph/tile_graph.h): every tile steps its own
// samples with a 2-sample halo refreshed every time step, with the time step from the deepest water over all tiles
// (pipe_across_tiles.cpp). Registered for the node type; tests call this entry point too.
#include <memory>

#include "graph/domain.h"
#include "graph/tile_graph.h"
#include "nodes/erosion/pipe.h"

namespace orogen::erosion {

// The algorithm for `p` on `whole`. Throws NodeError where the whole-domain node would refuse the run (too much work).
std::unique_ptr<TileGraphAlgorithm> pipe_across_tiles(const PipeParams& p, const Domain& whole);

}  // namespace orogen::erosion
