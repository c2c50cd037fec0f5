#include "nodes/field/bicubic.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace orogen {

double catmull_rom(const Heightfield& f, double u, double v) {
  const int w = f.width(), h = f.height();
  // A NaN coordinate (from a NaN displacement) has no position: the lookup is NaN, never an index.
  if (std::isnan(u) || std::isnan(v)) return std::numeric_limits<double>::quiet_NaN();
  u = std::clamp(u, 0.0, static_cast<double>(w - 1));
  v = std::clamp(v, 0.0, static_cast<double>(h - 1));
  const int i = static_cast<int>(std::floor(u)), j = static_cast<int>(std::floor(v));
  double wu[4], wv[4];
  catmull_rom_weights(u - i, wu);
  catmull_rom_weights(v - j, wv);
  double sum = 0.0;
  for (int b = 0; b < 4; ++b) {
    const int jj = std::clamp(j - 1 + b, 0, h - 1);
    double row = 0.0;
    for (int a = 0; a < 4; ++a) row += wu[a] * f.at(std::clamp(i - 1 + a, 0, w - 1), jj);
    sum += wv[b] * row;
  }
  return sum;
}

}  // namespace orogen
