#pragma once
// The tiling's windows (cli/tiling.h) for the tests that run a tile-graph algorithm's tiles in one process: a field cut
// into a tile's window, and the tiles' maps put together on the whole domain (shared samples must agree bit for bit).
#include <cmath>
#include <cstring>
#include <memory>
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
