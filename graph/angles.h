#pragma once
// Angles: parameters are in degrees (docs/conventions.md); algorithms that need radians convert with this one
// factor, so a migration that turns a former radian value into degrees can pick the degree value that
// converts back to the very same radians (degrees_for_radians).
#include <cmath>
#include <numbers>

namespace orogen {

inline constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;

inline double radians_from_degrees(double degrees) { return degrees * kRadiansPerDegree; }

// The degree value d nearest to radians * 180 / pi for which radians_from_degrees(d) == radians exactly, when
// one lies within a few units in the last place; else the nearest value.
inline double degrees_for_radians(double radians) {
  const double nearest = radians / kRadiansPerDegree;
  if (!std::isfinite(nearest)) return nearest;
  double below = nearest, above = nearest;
  for (int k = 0; k < 8; ++k) {
    if (radians_from_degrees(below) == radians) return below;
    if (radians_from_degrees(above) == radians) return above;
    below = std::nextafter(below, -INFINITY);
    above = std::nextafter(above, INFINITY);
  }
  return nearest;
}

}  // namespace orogen
