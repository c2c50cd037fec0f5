#pragma once
// Crater: an impact crater on a level surface at base_height, with r the distance from `position` and R the
// rim radius:
//   r <= floor_radius:        base_height - depth                                   (flat floor)
//   floor_radius < r <= R:    base_height - depth + (depth + rim_height) s^2,
//                             s = (r - floor_radius) / (R - floor_radius)          (bowl, steepest at the rim)
//   r > R:                    base_height + rim_height (r / R)^-ejecta_exponent     (ejecta blanket)
// The floor lies `depth` below the surrounding surface and the rim crest rim_height above it; the ejecta thin
// as a power of the distance (exponent 3 after T. McGetchin, M. Settle and J. Head (1973), "Radial thickness
// variation in impact crater ejecta", Earth and Planetary Science Letters 20), with proportions after R. Pike
// (1977), "Size-dependence in the shape of fresh impact craters on the Moon" (depth ~0.2 and rim height
// ~0.04 of the diameter for simple craters).
#include <memory>

#include <glm/vec2.hpp>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

struct CraterParams {
  glm::dvec2 position{512.0, 512.0};  // m
  double radius = 200.0;              // m, rim crest radius, > 0
  double depth = 80.0;                // m below base_height, >= 0
  double rim_height = 16.0;           // m above base_height, >= 0
  double floor_radius = 0.0;          // m, 0 <= floor_radius < radius
  double ejecta_exponent = 3.0;       // > 0
  double base_height = 0.0;           // m
};

void check_crater(const CraterParams& p);  // NodeError naming "Crater" and the parameter
double crater_height(const CraterParams& p, double x, double y);
std::shared_ptr<Heightfield> crater_field(const Domain& domain, const CraterParams& p,
                                          const ExecContext* ctx = nullptr);

}  // namespace orogen
