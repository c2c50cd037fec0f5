#include "nodes/field/surface_derivatives.h"

#include <algorithm>

namespace orogen {
namespace {

// d/dk of v at index k of n samples spaced h apart.
template <class V>
double first_difference(const V& v, int k, int n, double h) {
  if (n < 2) return 0.0;
  if (n == 2) return (v(1) - v(0)) / h;
  if (k == 0) return (-3.0 * v(0) + 4.0 * v(1) - v(2)) / (2.0 * h);
  if (k == n - 1) return (3.0 * v(n - 1) - 4.0 * v(n - 2) + v(n - 3)) / (2.0 * h);
  return (v(k + 1) - v(k - 1)) / (2.0 * h);
}

template <class V>
double second_difference(const V& v, int k, int n, double h) {
  if (n < 3) return 0.0;
  const int c = std::clamp(k, 1, n - 2);
  return (v(c + 1) - 2.0 * v(c) + v(c - 1)) / (h * h);
}

}  // namespace

void gradient_at(const Heightfield& z, int i, int j, double& p, double& q) {
  const double hx = z.domain.spacing.x, hy = z.domain.spacing.y;
  p = first_difference([&](int k) { return static_cast<double>(z.at(k, j)); }, i, z.width(), hx);
  q = first_difference([&](int k) { return static_cast<double>(z.at(i, k)); }, j, z.height(), hy);
}

SurfaceDerivatives derivatives_at(const Heightfield& z, int i, int j) {
  const int w = z.width(), h = z.height();
  const double hx = z.domain.spacing.x, hy = z.domain.spacing.y;
  SurfaceDerivatives d;
  gradient_at(z, i, j, d.p, d.q);
  d.r = second_difference([&](int k) { return static_cast<double>(z.at(k, j)); }, i, w, hx);
  d.t = second_difference([&](int k) { return static_cast<double>(z.at(i, k)); }, j, h, hy);
  const auto px = [&](int row) {
    return first_difference([&](int k) { return static_cast<double>(z.at(k, row)); }, i, w, hx);
  };
  d.s = first_difference(px, j, h, hy);
  return d;
}

}  // namespace orogen
