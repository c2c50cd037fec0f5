#pragma once
// How the files of a tiled build are named: which tile is _x0_y0 and which way y counts. Orogen counts y from
// the south, as its world does; Unreal Engine's tiled landscape import and World Machine take _x0_y0 as the
// top-left (north-west) tile and count y down the rows, as the images are stored (north row first).
#include <optional>
#include <string>

#include <glm/vec2.hpp>

namespace orogen::cli {

enum class TileNaming { Orogen, Unreal };

// "orogen" or "unreal"; nothing for anything else.
std::optional<TileNaming> parse_tile_naming(const std::string& text);

// The index a tile is named by (and `--tile` picks) for the tile at `index` in Orogen's numbering (column from
// the west, row from the south) of a `counts` grid. Its own inverse.
glm::ivec2 named_tile_index(TileNaming naming, glm::ivec2 index, glm::ivec2 counts);

}  // namespace orogen::cli
