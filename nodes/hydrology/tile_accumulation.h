#pragma once
// D8 flow accumulation across tiles, exact (R. Barnes 2017, "Parallel non-divergent flow accumulation for trillion
// cell digital elevation models", Environmental Modelling & Software 92): the building block for FlowAccumulation's
// tile-graph distribution (not wired into the node yet, docs/distributed.md).
//
// Tiles share their border samples (cli/tiling.h), so a sample and a flow edge (a cell and its D8 receiver) can lie
// in several tiles; each is counted by exactly one, the lowest-numbered tile that holds it: a tile owns its samples
// but those on its first column or row when another tile lies before it, and takes the edges that do not lie
// wholly on such a column or row. Counts are whole cells (64-bit integers), so every sum is exact and the result
// equals the whole-domain accumulation for any tiling; a cell area times the count is then the same product on
// every tile. Weighted sums (rainfall) are not exact this way: floating-point sums depend on their order.
//
//  1. Each tile accumulates the cells it owns along the edges it takes (start_tile_accumulation): L(c) per cell,
//     and for every perimeter cell the next perimeter cell downstream along the tile's edges (its link).
//  2. The solve (solve_tile_accumulation) gets every tile's perimeter L and links: the accumulation of a perimeter
//     sample is the sum over the tiles holding it of L there plus, for each perimeter cell linking to it, what that
//     cell carries beyond its own tile's L. Flow paths descend, so the links form a DAG, solved in topological
//     order. Each tile gets, per perimeter cell, the inflow its own edges do not bring (Y).
//  3. Each tile accumulates again with the owned cells plus Y at its perimeter (finish_tile_accumulation): the
//     whole-domain counts on every sample of the tile.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

#include "nodes/hydrology/tile_fill.h"

namespace orogen::hydrology {

// The cells of a tile in an order where every cell comes before its receiver (Kahn's algorithm; `receiver` holds
// each cell's receiver, or -1). Throws std::invalid_argument, naming `what`, when a receiver lies outside the tile
// or the receivers form a cycle.
std::vector<std::int32_t> upstream_first(const std::vector<std::int32_t>& receiver, const char* what);

struct TileAccumulation {
  TileRect rect;
  glm::ivec2 domain{1, 1};
  std::vector<std::int32_t> receiver;  // per tile cell: tile cell index of the receiver along a taken edge, or -1
  std::vector<std::uint8_t> owned;     // per tile cell: counted by this tile
  std::vector<std::int64_t> local;     // L: owned cells upstream along taken edges, the cell included if owned
  std::vector<std::int32_t> link;      // per perimeter cell (perimeter order): next perimeter cell downstream, or -1
};

// Phase 1. `direction`: the D8 direction k (flow_routing.h) of every tile cell as on the whole domain (it may
// point out of the tile), kNoDirection for outlets and pits; rect.size, row-major.
TileAccumulation start_tile_accumulation(std::span<const std::uint8_t> direction, const TileRect& rect,
                                         glm::ivec2 domain_size);
// The tile's message: its rectangle, L and link of every perimeter cell.
std::string accumulation_message(const TileAccumulation& tile);
// Phase 2: every tile's message (indexed by tile) into every tile's answer (Y per perimeter cell). Throws
// std::invalid_argument on malformed messages or links that form a cycle.
std::vector<std::string> solve_tile_accumulation(std::span<const std::string_view> messages, glm::ivec2 domain_size);
// Phase 3: the number of cells draining through every tile cell (itself included), row-major.
std::vector<std::int64_t> finish_tile_accumulation(const TileAccumulation& tile, std::string_view answer);

}  // namespace orogen::hydrology
