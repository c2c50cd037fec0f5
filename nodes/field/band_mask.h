#pragma once
// Band mask: how well a value fits a preferred band [min, max], as in the ecosystem rules of SeamScape
// (Table 1: min, max and sharpness on elevation, relative elevation and slope) and the height / slope splat
// rules of Potter 2017. 1 inside the band, falling smoothly (Hermite smoothstep, C1) to 0 at `falloff` beyond
// either edge, 0 further out.
#include "nodes/common/smoothstep.h"

namespace orogen {

struct BandParams {
  double min = 0.0;
  double max = 1.0;
  double falloff = 0.0;  // width of the transition on each side, in the field's units; 0 = hard edges
};

// The transition width from SeamScape's dimensionless sharpness: (max - min) / sharpness, so sharpness 2 fades
// over half the band's width on each side and larger values give crisper edges.
inline double falloff_from_sharpness(double min, double max, double sharpness) {
  return sharpness > 0.0 ? (max - min) / sharpness : 0.0;
}

inline double band_mask_value(double v, const BandParams& b) {
  if (v >= b.min && v <= b.max) return 1.0;
  if (!(b.falloff > 0.0)) return 0.0;
  const double d = v < b.min ? b.min - v : v - b.max;
  return smoothstep01(1.0 - d / b.falloff);
}

}  // namespace orogen
