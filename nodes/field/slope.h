#pragma once
// Slope: the angle between the surface and the horizontal, in degrees (0 flat, 90 vertical), from the
// gradient in world units (surface_derivatives.h), so it does not depend on the resolution.
#include <cmath>
#include <memory>
#include <numbers>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

inline double slope_degrees(double p, double q) { return std::atan(std::hypot(p, q)) * (180.0 / std::numbers::pi); }

std::shared_ptr<Heightfield> slope_field(const Heightfield& z, const ExecContext* ctx = nullptr);

}  // namespace orogen
