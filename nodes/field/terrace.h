#pragma once
// Terraces: heights snapped towards evenly spaced levels, with a shaped riser between levels.
//
// With x = (h - base) / spacing, level k = floor(x) and u = x - k in [0, 1), the output is
//   base + (k + u^(1 / (1 - sharpness))) * spacing.
// sharpness 0 is the identity, 0.5 gives quadratic risers, 1 hard steps (flat treads, vertical risers).
// For sharpness < 1 the result is continuous and non-decreasing; every level base + k * spacing is a fixed
// point, so terracing never moves the top or bottom of a level.
#include <cmath>

namespace orogen {

struct TerraceParams {
  double base = 0.0;       // m, height of level 0
  double spacing = 10.0;   // m, height between levels, > 0
  double sharpness = 0.7;  // 0..1
};

inline double terrace_value(double h, const TerraceParams& p) {
  const double x = (h - p.base) / p.spacing;
  const double k = std::floor(x);
  const double u = x - k;
  double shaped = u;
  if (p.sharpness >= 1.0)
    shaped = 0.0;
  else if (p.sharpness > 0.0)
    shaped = std::pow(u, 1.0 / (1.0 - p.sharpness));
  return p.base + (k + shaped) * p.spacing;
}

// Terraces only inside [lo, hi] with `levels` levels there, identity outside. Continuous at both ends
// (lo and hi are levels), so the result stays non-decreasing.
inline double terrace_in_range(double h, double lo, double hi, int levels, double sharpness) {
  if (h <= lo || h >= hi) return h;
  return terrace_value(h, {lo, (hi - lo) / levels, sharpness});
}

}  // namespace orogen
