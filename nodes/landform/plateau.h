#pragma once
// Plateau: a flat top at base_height + height within `radius` of `position`, an escarpment of horizontal
// width escarpment_width around it, and base_height beyond. Across the escarpment, with
// t = (r + edge_roughness * n(x, y) - radius) / escarpment_width in [0, 1] (r the distance from the center, n
// a seeded fBm in about [-1, 1] of feature size edge_feature_size that frays the outline):
//   height (1 - t)^2 + base_height
// a sharp brink where the caprock ends (slope 2 height / escarpment_width) and a concave talus flattening
// toward the plain, the profile of a mesa.
#include <cstdint>
#include <memory>

#include <glm/vec2.hpp>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

struct PlateauParams {
  glm::dvec2 position{512.0, 512.0};  // m
  double radius = 250.0;              // m, > 0: radius of the flat top
  double height = 120.0;              // m above base_height
  double escarpment_width = 80.0;     // m, > 0
  double base_height = 0.0;           // m
  double edge_roughness = 40.0;       // m, >= 0: how far the outline wanders in and out
  double edge_feature_size = 150.0;   // m, > 0
  std::uint64_t seed = 0;
};

void check_plateau(const PlateauParams& p);  // NodeError naming "Plateau" and the parameter
std::shared_ptr<Heightfield> plateau_field(const Domain& domain, const PlateauParams& p,
                                           const ExecContext* ctx = nullptr);

}  // namespace orogen
