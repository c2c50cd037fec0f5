#pragma once
// Canyon: a channel cut along a polyline `path` (two or more points), as a height offset (<= 0) to add to a
// terrain. With d the distance from the (meandering) path, s the distance along it of the nearest point, D = depth *
// a(s) the local depth (a the smoothstep taper over taper_length at each end), the floor half-width w = floor_width / 2
// and the wall's horizontal width W = D / tan(wall_slope):
//   d <= w:           -D
//   w < d < w + W:    -D (1 - f'),  f = (d - w) / W the share of the wall climbed
//   d >= w + W:       0
// f' = f for smooth walls; with `terraces` N > 0 each of N steps is a flat bench over the first half of its
// width and a riser twice as steep over the second: f' = (k + max(0, 2g - 1)) / N, k = floor(f N), g = f N - k.
// The path meanders: the query point is displaced by `meander` times two seeded fBm fields (feature size
// meander_feature_size) before its distance to the path is taken.
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

struct CanyonParams {
  // m, 2 to 256 points, not all the same
  std::vector<glm::dvec2> path{{100.0, 700.0}, {480.0, 580.0}, {924.0, 300.0}};
  double depth = 120.0;                 // m, >= 0
  double floor_width = 40.0;            // m, >= 0
  double wall_slope = 55.0;             // deg, (0, 90)
  int terraces = 0;                     // 0 = smooth walls
  double taper_length = 100.0;          // m, >= 0
  double meander = 60.0;                // m, >= 0
  double meander_feature_size = 400.0;  // m, > 0
  std::uint64_t seed = 0;
};

void check_canyon(const CanyonParams& p);  // NodeError naming "Canyon" and the parameter
std::shared_ptr<Heightfield> canyon_field(const Domain& domain, const CanyonParams& p,
                                          const ExecContext* ctx = nullptr);

}  // namespace orogen
