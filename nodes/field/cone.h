#pragma once
// Cone: a volcano / hill primitive, height * max(0, 1 - d / radius) with d the distance from the center:
// `height` at the center, falling linearly (constant slope height / radius) to 0 at the radius.
#include <memory>

#include <glm/vec2.hpp>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

struct ConeParams {
  glm::dvec2 center{512.0, 512.0};  // m
  double radius = 400.0;            // m, > 0
  double height = 200.0;            // m at the center
};

std::shared_ptr<Heightfield> cone_field(const Domain& domain, const ConeParams& p, const ExecContext* ctx = nullptr);

}  // namespace orogen
