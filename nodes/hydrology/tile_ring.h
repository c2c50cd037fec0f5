#pragma once
// A tile's values grown by a one-sample ring from the tiles around it, for what looks one sample across a tile's
// border: the D8 direction, the flow proportions and the slope of a perimeter cell (the flow routing across tiles,
// nodes/hydrology/flow_across_tiles.cpp). Tiles share their border samples (cli/tiling.h), so the ring of a tile is
// its neighbours' second row or column from the shared border (their first, on a tile two samples wide).
//
// One round of a tile-graph run (graph/tile_graph.h): each tile sends the values within one sample of its
// perimeter (ring_message, O(perimeter)); the solve hands every tile the values of its ring (solve_rings), which
// lie in those bands of the tiles around it; each tile puts them around its own (with_ring). A sample held by
// several tiles must have the same value in each (bit for bit): they are copies of one whole-domain value.
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include "nodes/hydrology/tile_fill.h"

namespace orogen::hydrology {

// The tile's rectangle grown by one sample on every side, clipped to the domain.
TileRect ringed_rect(const TileRect& rect, glm::ivec2 domain_size);

// The tile's message: its rectangle and its values within one sample of its perimeter. `values`: rect.size,
// row-major.
std::string ring_message(std::span<const float> values, const TileRect& rect);
std::string ring_message(std::span<const double> values, const TileRect& rect);

// Every tile's message (indexed by tile) into every tile's answer: the values of its ring (the samples of
// ringed_rect outside the tile, row-major). Throws std::invalid_argument on malformed messages, a ring sample no
// tile holds, or tiles that disagree on a shared sample.
std::vector<std::string> solve_rings(std::span<const std::string_view> messages, glm::ivec2 domain_size);
// The same for the rings of double values (ring_message of doubles).
std::vector<std::string> solve_double_rings(std::span<const std::string_view> messages, glm::ivec2 domain_size);

// The tile's values on ringed_rect(rect, domain_size), row-major: its own, and its ring from `answer`.
std::vector<float> with_ring(std::span<const float> values, const TileRect& rect, glm::ivec2 domain_size,
                             std::string_view answer);
std::vector<double> with_ring(std::span<const double> values, const TileRect& rect, glm::ivec2 domain_size,
                              std::string_view answer);

// Two fields' rings in one round (a surface to route on and a field beside it): a message holds the two fields' ring
// messages, an answer their two answers (solve_ring_pairs), each behind its length. with_ring_pair puts both around
// the tile's own values.
std::string ring_pair_message(std::span<const float> first, std::span<const float> second, const TileRect& rect);
std::vector<std::string> solve_ring_pairs(std::span<const std::string_view> messages, glm::ivec2 domain_size);
std::pair<std::vector<float>, std::vector<float>> with_ring_pair(std::span<const float> first,
                                                                 std::span<const float> second, const TileRect& rect,
                                                                 glm::ivec2 domain_size, std::string_view answer);

// The inverse of with_ring: the tile's values (rect.size, row-major) out of `ringed_values` on
// ringed_rect(rect, domain_size), row-major.
template <class T>
std::vector<T> without_ring(std::span<const T> ringed_values, const TileRect& rect, glm::ivec2 domain_size) {
  const TileRect ringed = ringed_rect(rect, domain_size);
  const glm::ivec2 at = rect.first - ringed.first;
  std::vector<T> out;
  out.reserve(static_cast<std::size_t>(rect.size.x) * static_cast<std::size_t>(rect.size.y));
  for (int j = 0; j < rect.size.y; ++j) {
    const auto row = ringed_values.begin() + static_cast<std::ptrdiff_t>(at.y + j) * ringed.size.x + at.x;
    out.insert(out.end(), row, row + rect.size.x);
  }
  return out;
}

}  // namespace orogen::hydrology
