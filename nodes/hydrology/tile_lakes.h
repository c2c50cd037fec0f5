#pragma once
// Lakes across tiles, numbered as one machine numbers them: the second round of FillDepressions' and Lakes'
// tile-graph runs (nodes/hydrology/fill_across_tiles.cpp), after the spill levels (nodes/hydrology/tile_fill.h).
//
// A lake is a set of 8-connected wet cells (water above ground). One machine numbers the lakes it keeps 1, 2, ...
// in row-major order of their first cell (label_components). Across tiles:
//  1. each tile labels its own wet components (label_tile_lakes) and sends, per component, its first cell in the
//     whole domain, its deepest water and the cells it owns, plus the component of each perimeter cell;
//  2. the solve joins components through the samples neighbouring tiles share (every 8-neighbour pair lies in one
//     tile, so that is the only way a lake crosses a border), sums and compares per whole lake, keeps the lakes the
//     rule keeps and numbers them by first cell (solve_tile_lakes);
//  3. each tile maps its components to those numbers.
// A shared sample is owned by the tile before it along each axis (the last tile owns the domain's last row and
// column), so cell counts add up to the whole domain's.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>

#include "nodes/hydrology/tile_fill.h"

namespace orogen::hydrology {

// What a tile sends: its components (index k is component k + 1 of the tile's labels).
struct TileLakes {
  TileRect rect;
  std::vector<std::int64_t> first_cell;  // lowest row-major index in the whole domain
  std::vector<float> deepest;            // deepest water (water - ground), metres
  std::vector<std::int64_t> cells;       // cells the tile owns
  std::vector<std::int32_t> perimeter;   // component of each perimeter cell (perimeter_cells order), 0: dry
};

struct TileLakeLabels {
  std::vector<std::int32_t> label;  // per tile cell: component 1, 2, ... or 0 on dry ground
  TileLakes lakes;
};

// `water` and `ground` on the tile's samples (rect.size, row-major); `whole`: the whole domain's sample counts.
TileLakeLabels label_tile_lakes(std::span<const float> water, std::span<const float> ground, const TileRect& rect,
                                glm::ivec2 whole);

// Whether a whole lake is kept, from its deepest water and its cell count.
using KeepLake = std::function<bool(float deepest, std::int64_t cells)>;

// Per tile (indexed like `tiles`), per component: the lake number of the whole domain, 0 if not kept. Throws
// std::invalid_argument if the tiles' figures do not fit together.
std::vector<std::vector<std::int32_t>> solve_tile_lakes(const std::vector<TileLakes>& tiles, glm::ivec2 whole,
                                                        const KeepLake& keep);

std::string encode(const TileLakes& lakes);
TileLakes decode_tile_lakes(std::string_view bytes);

// The lakes round's solve on the tiles' encoded figures (encode): each tile's lake numbers as its answer.
std::vector<std::string> solve_lake_messages(std::span<const std::string_view> messages, glm::ivec2 whole,
                                             const KeepLake& keep);

}  // namespace orogen::hydrology
