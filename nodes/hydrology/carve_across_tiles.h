#pragma once
// FillDepressions with mode 'carve' across the tiles of a tiled or distributed build, exact (graph/tile_graph.h,
// docs/distributed.md): registered by FillDepressions' tile-graph factory (nodes/hydrology/fill_across_tiles.cpp).
#include <memory>

#include "graph/domain.h"
#include "graph/tile_graph.h"

namespace orogen::hydrology {

// The carve on the build's whole domain `whole`: depressions at most `max_depth` metres deep kept as filled lakes,
// the others breached (FillParams' max_depth); `epsilon` as the node's 'flats'.
std::unique_ptr<TileGraphAlgorithm> carve_across_tiles(const Domain& whole, double max_depth, bool epsilon);

}  // namespace orogen::hydrology
