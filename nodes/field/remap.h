#pragma once
// Linear remapping of values from an input range to an output range.
#include <algorithm>
#include <cmath>

namespace orogen {

struct RemapRange {
  double in_min = 0.0, in_max = 1.0;    // input range; in_min != in_max (either order)
  double out_min = 0.0, out_max = 1.0;  // output range (either order: a reversed range inverts)
  bool clamp = false;                   // clamp to the output range instead of extrapolating
};

// in_min maps exactly to out_min and in_max exactly to out_max (std::lerp is exact at its ends).
inline double remap_value(double h, const RemapRange& r) {
  double t = (h - r.in_min) / (r.in_max - r.in_min);
  if (r.clamp) t = std::clamp(t, 0.0, 1.0);
  return std::lerp(r.out_min, r.out_max, t);
}

}  // namespace orogen
