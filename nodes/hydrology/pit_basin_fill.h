#pragma once
// The Priority-Flood+epsilon fill (FlatMode::Epsilon, flow_routing.h) of the pit basins of a surface alone: the cells
// whose D8 path ends in a pit rather than at an outlet, given with their 8-neighbours outside them. Every other cell
// keeps its height in the whole-domain fill (it descends strictly to an outlet, so its flat level is its height and
// one ulp above its receiver is no more than its height), so the basins' fill from the heights of the cells around
// them is the whole-domain fill there, bit for bit: the flat level is the minimax height over paths to those cells
// (a Priority-Flood from them), and the epsilon surface the least fixed point of e(n) = max(level(n), min over
// neighbours next_up(e(m))), both unique whatever order ties are taken in. StreamPower across tiles fills this way
// when the pit basins are small (nodes/erosion/stream_power_across_tiles.cpp): O(basins) instead of a whole fill.
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/vec2.hpp>

namespace orogen::hydrology {

struct BasinSample {
  std::int64_t sample = 0;  // row-major index in the domain
  float z = 0.0f;           // the surface's height there
  bool inside = false;      // in a pit basin (filled), else around one (fixed)
};

// The filled heights of the samples inside, as (sample, height) in increasing sample order. Samples given more than
// once must agree on their height (inside if any copy says so). Throws std::invalid_argument on a disagreement, a
// sample outside a `domain`-sample domain, or an inside sample with a neighbour missing.
std::vector<std::pair<std::int64_t, float>> fill_pit_basins(std::vector<BasinSample> samples, glm::ivec2 domain);

}  // namespace orogen::hydrology
