#pragma once
// StreamPower across the tiles of a tiled or distributed build, exact (graph/tile_graph.h,
// stream_power_across_tiles.cpp): with `depressions: priority_flood`, every tile's outputs equal the whole-domain
// run's (StreamPowerParams::Depressions::PriorityFlood) bit for bit, for any tiling. Registered for the node type;
// this entry point serves the tests.
#include <cstddef>
#include <memory>
#include <optional>

#include "graph/domain.h"
#include "graph/tile_graph.h"
#include "nodes/erosion/stream_power.h"

namespace orogen::erosion {

// The algorithm for `p` (its depressions must be PriorityFlood) on `whole`. A step whose pit basins hold at most
// `largest_gathered_basins` cells of every tile fills them in one piece (nodes/hydrology/pit_basin_fill.h), else
// across the tiles (nodes/hydrology/tile_fill.h); by default 1/16 of the tile's cells or 1024. Throws NodeError where
// the whole-domain run would refuse the step counts.
std::unique_ptr<TileGraphAlgorithm> stream_power_across_tiles(const StreamPowerParams& p, const Domain& whole,
                                                              std::optional<std::size_t> largest_gathered_basins = {});

}  // namespace orogen::erosion
