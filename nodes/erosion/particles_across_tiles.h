#pragma once
// HydraulicErosion (particles.h) across the tiles of a tiled or distributed build, exact (graph/tile_graph.h): the
// whole-domain run's own schedule (droplet_schedule.h), a round per phase, each block's droplets run by the tile
// holding the block's center, the samples they changed sent to the tiles that hold them (particles_across_tiles.cpp).
#include <memory>

#include "graph/domain.h"
#include "graph/tile_graph.h"
#include "nodes/erosion/particles.h"

namespace orogen::erosion {

// The algorithm for `p` on `whole`. Throws NodeError where the whole-domain node would refuse the droplet count or
// the work. The outputs of each tile: out, erosion, deposition, flow (all of them, whatever p.change_maps and
// p.flow_map say), and the report, the whole domain's, the same on every tile.
std::unique_ptr<TileGraphAlgorithm> particles_across_tiles(const ParticleParams& p, const Domain& whole);

}  // namespace orogen::erosion
