#pragma once
// SunIllumination across the tiles of a tiled or distributed build, exact (graph/tile_graph.h): every sun direction's
// horizon sweep passes from tile to tile along the sweep, as a wavefront of rounds (sun_across_tiles.cpp). Registered
// for the node type; this entry point lets tests run it with given parameters.
#include <memory>
#include <vector>

#include "graph/domain.h"
#include "graph/tile_graph.h"
#include "nodes/climate/sun.h"

namespace orogen::climate {

// The algorithm on `whole` for the daily outputs of `months` (1..12, one image channel each) and the instant outputs
// at (`month`, `hour`). Throws NodeError on parameters the whole-domain node refuses.
std::unique_ptr<TileGraphAlgorithm> sun_across_tiles(const SunParams& p, std::vector<int> months, int month,
                                                     double hour, const Domain& whole);

}  // namespace orogen::climate
