#include "nodes/hydrology/tile_surface_memo.h"

#include <bit>
#include <map>
#include <mutex>
#include <tuple>

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

inline std::uint64_t mix(std::uint64_t h) {  // the murmur3 finalizer
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  return h ^ (h >> 33);
}

}  // namespace

HeightsHash hash_heights(std::span<const float> heights) {
  // Two independent polynomial hashes of the bit patterns, finalized: 128 bits, so two different tiles of heights
  // collide with a probability of about 2^-128 per pair.
  std::uint64_t a = 0x9e3779b97f4a7c15ull ^ heights.size(), b = 0xc2b2ae3d27d4eb4full + heights.size();
  for (const float v : heights) {
    const std::uint64_t x = std::bit_cast<std::uint32_t>(v);
    a = (a ^ x) * 0x100000001b3ull;
    b = (b + x) * 0xff51afd7ed558ccdull + 0x165667b19e3779f9ull;
  }
  return {mix(a), mix(b ^ a)};
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
