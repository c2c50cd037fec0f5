#pragma once
// WaterFlow across the tiles of a tiled or distributed build, exact (graph/tile_graph.h): the same depth, flux and
// report as the whole-domain node (nodes/hydrology/water_flow.h) for any tiling. The node registers it; this entry
// point lets tests fix the iterations per exchange.
#include <memory>

#include "graph/domain.h"
#include "graph/tile_graph.h"
#include "nodes/hydrology/water_flow.h"

namespace orogen::hydrology {

// The algorithm for `p` on `whole`; `iterations_per_exchange` 0 chooses it from the smallest tile (one per 64 samples
// of its side, 1 to 8). Throws NodeError where the whole-domain node would refuse the work.
std::unique_ptr<TileGraphAlgorithm> water_flow_across_tiles(const WaterFlowParams& p, const Domain& whole,
                                                            int iterations_per_exchange = 0);

}  // namespace orogen::hydrology
