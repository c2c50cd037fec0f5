#pragma once
// Carving (breaching) depressions across tiles, exact: the last phase of FillDepressions' carve mode across the tiles
// of a tiled or distributed build (nodes/hydrology/carve_across_tiles.cpp). The whole-domain carve
// (breach_depressions) sends every pit's height down the D8 tree of the epsilon surface, each cell ending at the
// lowest value that reaches it (nodes/hydrology/breach_rule.h); every step is a minimum, so the same values can be
// found tile by tile:
//  1. each tile, given its heights and their epsilon surface with the one-sample ring around it (tile_ring.h), finds
//     its cells' receivers and pits as the whole domain does, and carries the values down its own part of the tree;
//  2. rounds exchange the values that reached its perimeter cells (PerimeterMinima): a sample shared by several
//     tiles takes the lowest any of them found, since each saw some of its donors (every 8-neighbour pair, so every
//     tree edge, lies in one tile), and a tile carries the values that fell on down its tree;
//  3. when a round lowers nothing, every cell has the lowest value over all its donors: the whole-domain carve bit
//     for bit. The rounds grow with the number of tiles a carved channel crosses.
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

#include "nodes/hydrology/tile_fill.h"

namespace orogen::hydrology {

class TileBreach {
 public:
  // `ground` (the heights to carve) and `surface` (their epsilon surface), each on ringed_rect(rect, domain_size),
  // row-major; `dx`, `dy` the domain's spacing (the D8 slopes); `epsilon` as breach_depressions' FlatMode::Epsilon.
  TileBreach(std::span<const float> ground, std::span<const float> surface, const TileRect& rect,
             glm::ivec2 domain_size, double dx, double dy, bool epsilon);
  // The values that reached perimeter cells and fell since the last message (PerimeterMinima).
  std::string message() { return minima_.message(arrived_); }
  // The lowest values of this tile's shared samples (solve_perimeter_minima): carried down from those that fell.
  void answer(std::string_view bytes);
  // The carved heights on the tile (rect.size, row-major).
  std::vector<float> carved() const;

 private:
  // Carries cell c's value down the tile's tree while it lowers what reaches the next cell.
  void carry(std::int32_t c);

  bool epsilon_;
  std::vector<float> ground_;           // the tile's heights
  std::vector<std::int32_t> receiver_;  // per tile cell: its receiver in the tile, or -1 (an outlet, or beyond)
  std::vector<std::uint8_t> pit_;
  std::vector<float> arrived_;  // per tile cell: the lowest value that reached it so far (+inf: none)
  PerimeterMinima minima_;
};

}  // namespace orogen::hydrology
