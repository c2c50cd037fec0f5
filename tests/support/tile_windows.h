#pragma once
// The tiling's windows (cli/tiling.h) for the tests that run a tile-graph algorithm's tiles in one process: a field cut
// into a tile's window, and the tiles' maps put together on the whole domain (shared samples must agree bit for bit).
#include <cmath>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <gtest/gtest.h>

#include "graph/domain.h"
#include "graph/heightfield.h"

namespace orogen::test {

// Tile I of N over W samples: [floor(I (W-1) / N), floor((I+1) (W-1) / N)] (cli/tiling.h).
inline int edge(int t, int samples, int tiles) {
  return static_cast<int>(static_cast<long long>(t) * (samples - 1) / tiles);
}

// "NxM": a tiling's counts, as --tiles takes them.
inline std::string tiles_text(glm::ivec2 counts) { return std::to_string(counts.x) + "x" + std::to_string(counts.y); }

// The tilings of the tests on 41 x 33 terrains; the last: tiles of two samples (a neighbor's ring is its whole tile).
inline const std::vector<glm::ivec2> kTilings = {{1, 1}, {2, 2}, {3, 2}, {4, 3}, {1, 4}, {7, 6}, {40, 32}};

// The lowest-numbered tile of `counts` holding sample (i, j) of a domain of `size` samples.
inline int tile_of(int i, int j, glm::ivec2 size, glm::ivec2 counts) {
  auto index = [](int s, int samples, int tiles) {
    int t = 0;
    while (t + 1 < tiles && edge(t + 1, samples, tiles) < s) ++t;
    return t;
  };
  return index(j, size.y, counts.y) * counts.x + index(i, size.x, counts.x);
}

// `h` (on `domain`) in the window of `n` samples from `first`.
inline HeightfieldPtr crop(const Domain& domain, const HeightfieldPtr& h, glm::ivec2 first, glm::ivec2 n) {
  auto c = std::make_shared<Heightfield>(domain.subdomain(first.x, first.y, n.x, n.y));
  for (int j = 0; j < n.y; ++j)
    for (int i = 0; i < n.x; ++i) c->at(i, j) = h->at(first.x + i, first.y + j);
  return HeightfieldPtr(c);
}

// Puts a tile's map `h` into `joined` (row-major, `width` samples a row). A sample already there that differs counts
// in `disagreements`, or fails the test without it.
inline void join_tile_map(std::vector<float>& joined, const Heightfield& h, int width, int* disagreements) {
  for (int j = 0; j < h.height(); ++j)
    for (int i = 0; i < h.width(); ++i) {
      float& v = joined[static_cast<std::size_t>(h.domain.first.y + j) * width + h.domain.first.x + i];
      const float mine = h.at(i, j);
      if (!std::isnan(v) && std::memcmp(&v, &mine, sizeof v) != 0) {
        if (disagreements)
          ++*disagreements;
        else
          ADD_FAILURE() << "tiles disagree on a shared sample";
      }
      v = mine;
    }
}

}  // namespace orogen::test
