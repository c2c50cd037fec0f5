#pragma once
// Bicubic Catmull-Rom interpolation of a field: interpolating (exact at samples), C1, reproduces linear
// functions exactly. Used where bilinear lookups would blur or facet (Warp).
#include "graph/heightfield.h"

namespace orogen {

// Value at continuous sample coordinates (column u, row v). Coordinates are clamped to the grid and the
// 4x4 taps repeat the edge samples beyond it.
double catmull_rom(const Heightfield& f, double u, double v);

// Catmull-Rom weights of the taps at -1, 0, 1, 2 for a fraction t in [0, 1].
inline void catmull_rom_weights(double t, double w[4]) {
  const double t2 = t * t, t3 = t2 * t;
  w[0] = 0.5 * (-t3 + 2.0 * t2 - t);
  w[1] = 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
  w[2] = 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
  w[3] = 0.5 * (t3 - t2);
}

}  // namespace orogen
