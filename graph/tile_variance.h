#pragma once
// A node type whose reach is global but which declares Distribution::PerTile promises that a tile's evaluation
// gives exactly the untiled result's part of the tile (hashed scatterings draw every candidate from its world
// cell). Some keep that promise only for some parameter values: PoissonDisk with `fill_border` samples up to the
// edges of the domain it is asked for, a tile's in a tiled build. Such a type registers why here (at static
// initialisation, next to its declaration); the tiled build then computes it on the whole domain and hands each
// tile its part (cli/tiling.h), as for any other node whose result depends on the whole domain.
#include <functional>
#include <string>
#include <vector>

#include "graph/param_value.h"

namespace orogen {

class ParamView;
struct NodeType;

// Why these parameter values make the type's result depend on the domain it is asked for ("" if they do not).
using TileVariance = std::function<std::string(const ParamView& params)>;

bool register_tile_variance(const std::string& type, TileVariance why);
// The registered reason for these effective parameter values (declaration order), "" if none.
std::string tile_variance(const NodeType& type, const std::vector<ParamValue>& params);

}  // namespace orogen
