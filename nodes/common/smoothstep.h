#pragma once
// The Hermite step every family fades masks and weights with (band masks, splat terms, ecosystem preferences,
// river carving), so they all share one curve.
#include <algorithm>

namespace orogen {

// t clamped to [0, 1], then t^2 (3 - 2t): 0 at 0, 1 at 1, zero slope at both ends (C1). NaN stays NaN.
inline double smoothstep01(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

}  // namespace orogen
