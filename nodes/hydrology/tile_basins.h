#pragma once
// D8 drainage basins across tiles, exact (Watersheds in a tiled or distributed build, after Barnes 2017's perimeter
// links): every cell labeled with the outlet its D8 path reaches, basins numbered by decreasing area (ties by
// outlet index) over the whole domain, as watersheds() does on one grid (nodes/hydrology/flow.h).
//
// The D8 edges are those of start_tile_accumulation (nodes/hydrology/tile_accumulation.h): each edge, and each
// shared sample, taken by exactly one tile.
//  1. Each tile follows its own edges from every cell to where they stop (start_tile_basins): an outlet or pit
//     inside the tile, or a perimeter cell whose edge another tile takes (or that is itself an outlet). It sends,
//     per perimeter cell, that end (basin_links_message).
//  2. The solve joins the ends of all tiles into every perimeter sample's outlet (solve_basin_links).
//  3. Each tile labels its cells with their outlets (take_basin_outlets) and sends, per outlet, the number of cells
//     it owns that drain there (basin_count_message).
//  4. The solve adds the counts (whole numbers, exact), numbers the basins by decreasing count, ties by outlet
//     index, drops those under the minimum area, and tells each tile the number and count of each of its outlets
//     (solve_basin_counts); the tile writes its maps (basin_maps).
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "nodes/hydrology/tile_accumulation.h"

namespace orogen::hydrology {

struct TileBasins {
  TileRect rect;
  glm::ivec2 domain{1, 1};
  std::vector<std::uint8_t> owned;    // per tile cell: counted by this tile
  std::vector<std::int32_t> end;      // per tile cell: the tile cell where its path along the tile's edges stops
  std::vector<std::int64_t> outlet;   // per tile cell, after take_basin_outlets: its outlet's sample index
  std::vector<std::int64_t> outlets;  // after basin_count_message: the outlets of its cells, increasing
};

// Phase 1, from the tile's edges (start_tile_accumulation).
TileBasins start_tile_basins(const TileAccumulation& edges);
// Per perimeter cell: the perimeter cell its path stops at (or -1), or the sample of the outlet inside the tile.
std::string basin_links_message(const TileBasins& tile);
// Phase 2: every tile's message (indexed by tile) into every tile's answer (the outlet of each perimeter cell).
// Throws std::invalid_argument on malformed messages, an edge taken twice, or links that loop.
std::vector<std::string> solve_basin_links(std::span<const std::string_view> messages, glm::ivec2 domain_size);
// Phase 3: the outlet of every cell of the tile.
void take_basin_outlets(TileBasins& tile, std::string_view answer);
// The tile's outlets and the number of its owned cells draining to each.
std::string basin_count_message(TileBasins& tile);
// Phase 4: every tile's counts into every tile's answer: per outlet of its message, the basin number (0 under
// `min_area`) and the basin's cell count. Throws std::invalid_argument on malformed messages.
std::vector<std::string> solve_basin_counts(std::span<const std::string_view> messages, double cell_area,
                                            double min_area);
// The basin number and area (count x cell area) of every cell of the tile, row-major, as watersheds() writes them.
void basin_maps(const TileBasins& tile, std::string_view answer, double cell_area, std::span<float> id,
                std::span<float> area);

}  // namespace orogen::hydrology
