#pragma once
// Ridge: a crest along the segment from `start` to `end`. With d the distance to the segment, s the distance
// along it of the nearest point (0..L), u = d / half_width and the cross profile
//   c(u) = (1 - sharpness) (1 - 3u^2 + 2u^3) + sharpness (1 - u)^2     for u < 1, else 0
// (a rounded bell at sharpness 0, a knife-edge crest with concave flanks at 1; both reach 0 with zero slope at
// the foot), the height is
//   height * a(s) * c(u),   a(s) = smoothstep(min(s, L - s) / taper_length)   (a = 1 when taper_length is 0)
// so the crest runs at `height` along the segment and comes down to the ground at both ends. Two seeded
// noises break the straight line: the sample is displaced by `meander` times two fBm fields before its
// distance to the segment is taken (the crest bends), and `roughness` times a ridged multifractal minus 1/2
// is added to the height under the same envelope (spurs and gullies on the flanks, the crest rising and
// falling by up to roughness / 2); both have feature size feature_size.
#include <cstdint>
#include <memory>

#include <glm/vec2.hpp>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

struct RidgeParams {
  glm::dvec2 start{200.0, 300.0};  // m
  glm::dvec2 end{824.0, 724.0};    // m, != start
  double height = 200.0;           // m on the crest
  double half_width = 150.0;       // m, > 0: crest to foot
  double sharpness = 0.6;          // 0..1
  double taper_length = 150.0;     // m, >= 0
  double meander = 40.0;           // m, >= 0
  double roughness = 60.0;         // m, >= 0
  double feature_size = 250.0;     // m, > 0
  std::uint64_t seed = 0;
};

void check_ridge(const RidgeParams& p);  // NodeError naming "Ridge" and the parameter
// height * a(s) * c(u) at a point whose meander displacement has already been applied, without roughness.
double ridge_height(const RidgeParams& p, double x, double y);
std::shared_ptr<Heightfield> ridge_field(const Domain& domain, const RidgeParams& p, const ExecContext* ctx = nullptr);

}  // namespace orogen
