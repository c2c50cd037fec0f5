#pragma once
// Surface curvature in 1/m from first and second derivatives (p, q, r, s, t; surface_derivatives.h),
// with g2 = p^2 + q^2:
//   profile    = -(p^2 r + 2pq s + q^2 t) / (g2 (1 + g2)^1.5)   normal curvature along the slope line
//   plan       = -(q^2 r - 2pq s + p^2 t) / g2^1.5              curvature of the contour line (horizontal)
//   tangential = -(q^2 r - 2pq s + p^2 t) / (g2 (1 + g2)^0.5)   normal curvature along the contour
//   mean       = -((1 + q^2) r - 2pq s + (1 + p^2) t) / (2 (1 + g2)^1.5)
// Sign convention: positive where the surface is convex (bulging up: summits, ridge crests, spurs),
// negative where concave (valleys, hollows, foot slopes); a sphere cap of radius R has profile, tangential
// and mean curvature 1/R and plan curvature 1/rho at horizontal distance rho from its top. Profile, plan
// and tangential curvature need a direction; they are 0 where the gradient is exactly zero.
#include <memory>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "nodes/field/surface_derivatives.h"

namespace orogen {

enum class CurvatureKind { Profile, Plan, Tangential, Mean };

double curvature_value(const SurfaceDerivatives& d, CurvatureKind kind);

std::shared_ptr<Heightfield> curvature_field(const Heightfield& z, CurvatureKind kind,
                                             const ExecContext* ctx = nullptr);

}  // namespace orogen
