#pragma once
// The epsilon-filled surface of each tile, kept after a flow node filled it across the tiles, so that the next flow
// node on the same heights (FlowDirection, FlowAccumulation and Watersheds often share their terrain) takes it instead
// of filling again (nodes/hydrology/flow_across_tiles.cpp, docs/distributed.md).
//
// A surface is found by the tile's rectangle, the whole domain's size and XXH3's 128-bit hash of the tile's input
// heights. One surface is kept per tile rectangle (the latest), so the memo holds at most one float per sample of the
// tiles this process runs. Whether a tile finds its surface is decided by every tile together (one round): the tiles
// run the fill's rounds unless all of them found theirs, so tiles on different ranks never disagree on the phase.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include <glm/vec2.hpp>

#include "nodes/hydrology/tile_fill.h"

namespace orogen::hydrology {

struct HeightsHash {
  std::uint64_t a = 0, b = 0;
  bool operator==(const HeightsHash&) const = default;
};
HeightsHash hash_heights(std::span<const float> heights);

// The kept surface of the tile, or null.
std::shared_ptr<const std::vector<float>> find_filled_surface(const TileRect& rect, glm::ivec2 whole,
                                                              const HeightsHash& heights);
// Keeps `surface` for the tile (replacing what was kept for its rectangle).
void keep_filled_surface(const TileRect& rect, glm::ivec2 whole, const HeightsHash& heights,
                         std::vector<float> surface);
// Forgets every kept surface (tests that must run the fill's rounds).
void forget_filled_surfaces();

}  // namespace orogen::hydrology
