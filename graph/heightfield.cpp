#include "graph/heightfield.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <cmath>

namespace orogen {

float Heightfield::clamped(int i, int j) const {
  i = std::clamp(i, 0, width() - 1);
  j = std::clamp(j, 0, height() - 1);
  return at(i, j);
}

float Heightfield::bilinear(double u, double v) const {
  if (std::isnan(u) || std::isnan(v)) return std::numeric_limits<float>::quiet_NaN();  // no position, no index
  u = std::clamp(u, 0.0, static_cast<double>(width() - 1));
  v = std::clamp(v, 0.0, static_cast<double>(height() - 1));
  const int i = std::min(static_cast<int>(u), std::max(width() - 2, 0));
  const int j = std::min(static_cast<int>(v), std::max(height() - 2, 0));
  const double fu = u - i, fv = v - j;
  const double a = clamped(i, j), b = clamped(i + 1, j), c = clamped(i, j + 1), d = clamped(i + 1, j + 1);
  return static_cast<float>((a * (1 - fu) + b * fu) * (1 - fv) + (c * (1 - fu) + d * fu) * fv);
}

float Heightfield::sample_world(double x, double y) const {
  const auto s = domain.to_sample({x, y});
  return bilinear(s.x, s.y);
}

}  // namespace orogen
