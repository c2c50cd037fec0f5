#pragma once
// The hilly test terrain of the routing tests (test_hydrology_routing.cpp, test_basin_graph.cpp): two waves
// and white noise, so it has closed depressions of every size.
#include <cmath>
#include <cstdint>
#include <vector>

#include "nodes/hydrology/flow_routing.h"

namespace orogen::test {

// Deterministic white noise in [0, 1) from an integer (a 32-bit avalanche hash).
inline float hash01(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return static_cast<float>(x >> 8) / 16777216.0f;
}

// Heights in metres: 40 m and 25 m waves plus `noise` metres of white noise keyed by `seed`; `phase` shifts
// the first wave (radians), so seeds can move the hills as well as the noise.
inline std::vector<float> depression_terrain(const hydrology::FlowGrid& g, std::uint32_t seed, double noise = 3.0,
                                             double phase = 0.0) {
  std::vector<float> z(g.size());
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const double x = i * g.dx, y = j * g.dy;
      z[g.index(i, j)] = static_cast<float>(40.0 * std::sin(x / 37.0 + phase) * std::cos(y / 29.0) +
                                            25.0 * std::sin((x + 2 * y) / 71.0) +
                                            noise * hash01(seed * 7919u + static_cast<std::uint32_t>(g.index(i, j))));
    }
  return z;
}

}  // namespace orogen::test
