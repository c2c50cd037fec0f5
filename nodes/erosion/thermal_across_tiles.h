#pragma once
// ThermalErosion across the tiles of a tiled or distributed build, exact (graph/tile_graph.h): tiles iterate on their
// own samples and exchange halos every few iterations (thermal_across_tiles.cpp). Registered for the node type; this
// entry point lets tests fix the iterations per exchange.
#include <memory>

#include "graph/domain.h"
#include "graph/tile_graph.h"
#include "nodes/erosion/thermal.h"

namespace orogen::erosion {

// The algorithm for `p` on `whole`; `iterations_per_exchange` 0 chooses it from the smallest tile (one per 64
// samples of its side, 1 to 8). Throws NodeError where the whole-domain node would refuse the iteration count.
std::unique_ptr<TileGraphAlgorithm> thermal_across_tiles(const ThermalParams& p, const Domain& whole,
                                                         int iterations_per_exchange = 0);

}  // namespace orogen::erosion
