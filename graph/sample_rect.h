#pragma once
// A rectangle of samples of the whole domain, as runs across tiles name a tile, its bands, the reach of a block of
// droplets (nodes/erosion/*_across_tiles.cpp) or the piece of a result another tile needs (cli/tile_graph_stages.cpp).
#include <cstddef>
#include <cstdint>
#include <tuple>
#include <type_traits>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include "graph/domain.h"

namespace orogen {

// [lo, hi], both ends included; empty when hi < lo on either axis. It travels in messages as its four int32 (lo.x,
// lo.y, hi.x, hi.y) through bytes::put and bytes::take (graph/tile_bytes.h).
struct SampleRect {
  glm::ivec2 lo{0, 0}, hi{-1, -1};
  bool empty() const { return hi.x < lo.x || hi.y < lo.y; }
  glm::ivec2 size() const { return hi - lo + 1; }
  std::size_t area() const { return empty() ? 0 : static_cast<std::size_t>(size().x) * size().y; }
  bool contains(glm::ivec2 s) const { return s.x >= lo.x && s.x <= hi.x && s.y >= lo.y && s.y <= hi.y; }
  bool within(const SampleRect& o) const { return !empty() && o.contains(lo) && o.contains(hi); }
  bool operator==(const SampleRect& o) const { return lo == o.lo && hi == o.hi; }
  bool operator<(const SampleRect& o) const {
    return std::tie(lo.x, lo.y, hi.x, hi.y) < std::tie(o.lo.x, o.lo.y, o.hi.x, o.hi.y);
  }
};
static_assert(std::is_trivially_copyable_v<SampleRect> && sizeof(SampleRect) == 4 * sizeof(std::int32_t),
              "a SampleRect travels as its four int32");

inline SampleRect overlap(const SampleRect& a, const SampleRect& b) {
  return {glm::max(a.lo, b.lo), glm::min(a.hi, b.hi)};
}
inline SampleRect bounding(const SampleRect& a, const SampleRect& b) {
  return {glm::min(a.lo, b.lo), glm::max(a.hi, b.hi)};
}

// The samples of `tile` in the whole domain `whole` (the same lattice).
inline SampleRect rect_of(const Domain& tile, const Domain& whole) {
  const glm::ivec2 lo = tile.first - whole.first;
  return {lo, lo + tile.resolution - 1};
}

}  // namespace orogen
