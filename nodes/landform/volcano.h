#pragma once
// Volcano: a cone with a summit crater. With r the distance from `position`:
//   r <= crater_radius:            height - crater_depth * (1 - (r / crater_radius)^2)   (a paraboloid bowl)
//   crater_radius < r < radius:    height * ((radius - r) / (radius - crater_radius))^flank_exponent
//   r >= radius:                   0
// The rim, at crater_radius, is the highest ring (`height`); the crater floor at the center lies
// crater_depth below it. flank_exponent 1 gives straight flanks (cinder cones, C. A. Wood 1980); above 1
// concave flanks steepening toward the summit, as on stratovolcanoes; below 1 a convex dome.
#include <memory>

#include <glm/vec2.hpp>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

struct VolcanoParams {
  glm::dvec2 position{512.0, 512.0};  // m
  double radius = 500.0;              // m, base radius, > crater_radius
  double height = 250.0;              // m, rim height
  double flank_exponent = 1.5;        // > 0
  double crater_radius = 60.0;        // m, >= 0
  double crater_depth = 50.0;         // m, >= 0, below the rim
};

// Throws NodeError (naming "Volcano" and the parameter) on inconsistent parameters.
void check_volcano(const VolcanoParams& p);
double volcano_height(const VolcanoParams& p, double x, double y);
std::shared_ptr<Heightfield> volcano_field(const Domain& domain, const VolcanoParams& p,
                                           const ExecContext* ctx = nullptr);

}  // namespace orogen
