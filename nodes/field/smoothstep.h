#pragma once
// Smooth and hard thresholds that turn a field into a 0..1 mask.
#include "nodes/common/smoothstep.h"

namespace orogen {

// 0 at edge0, 1 at edge1, Hermite t^2 (3 - 2t) between (C1). edge0 > edge1 gives a falling mask;
// edge0 == edge1 a hard step (1 where h >= edge0).
inline double smoothstep_value(double h, double edge0, double edge1) {
  if (edge0 == edge1) return h >= edge0 ? 1.0 : 0.0;
  return smoothstep01((h - edge0) / (edge1 - edge0));
}

}  // namespace orogen
