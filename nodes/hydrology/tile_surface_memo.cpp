#include "nodes/hydrology/tile_surface_memo.h"

#include <map>
#include <mutex>
#include <tuple>

#include <xxhash.h>

namespace orogen::hydrology {
namespace {

struct Kept {
  HeightsHash heights;
  std::shared_ptr<const std::vector<float>> surface;
};

using Key = std::tuple<int, int, int, int, int, int>;  // whole size, tile first, tile size

Key key_of(const TileRect& rect, glm::ivec2 whole) {
  return {whole.x, whole.y, rect.first.x, rect.first.y, rect.size.x, rect.size.y};
}

std::mutex& memo_mutex() {
  static std::mutex m;
  return m;
}
std::map<Key, Kept>& memo() {
  static std::map<Key, Kept> m;
  return m;
}

}  // namespace

HeightsHash hash_heights(std::span<const float> heights) {
  // XXH3's 128-bit hash of the heights' bit patterns (the byte count included). It is not cryptographic: for heights
  // not crafted to collide, two different tiles of heights collide about as often as two random 128-bit values
  // (2^-128 per pair), far below any other failure; a collision would hand a tile another tile's filled surface.
  const XXH128_hash_t h = XXH3_128bits(heights.data(), heights.size_bytes());
  return {h.low64, h.high64};
}

std::shared_ptr<const std::vector<float>> find_filled_surface(const TileRect& rect, glm::ivec2 whole,
                                                              const HeightsHash& heights) {
  std::lock_guard lock(memo_mutex());
  const auto it = memo().find(key_of(rect, whole));
  if (it == memo().end() || !(it->second.heights == heights)) return nullptr;
  return it->second.surface;
}

void keep_filled_surface(const TileRect& rect, glm::ivec2 whole, const HeightsHash& heights,
                         std::vector<float> surface) {
  auto kept = std::make_shared<const std::vector<float>>(std::move(surface));
  std::lock_guard lock(memo_mutex());
  memo()[key_of(rect, whole)] = {heights, std::move(kept)};
}

void forget_filled_surfaces() {
  std::lock_guard lock(memo_mutex());
  memo().clear();
}

}  // namespace orogen::hydrology
