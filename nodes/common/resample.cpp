#include "nodes/common/resample.h"

#include <cmath>

namespace orogen {
namespace {

// Sample coordinates within this distance of an integer are treated as exactly on the lattice.
constexpr double kSnap = 1e-7;

double snap(double u) {
  const double r = std::round(u);
  return std::abs(u - r) < kSnap ? r : u;
}

}  // namespace

void resample_bilinear_row(const Heightfield& source, const Domain& target, int j, std::span<float> out) {
  const double v = snap(source.domain.to_sample({0.0, target.y(j)}).y);
  for (int i = 0; i < target.width(); ++i) {
    const double u = snap(source.domain.to_sample({target.x(i), 0.0}).x);
    out[static_cast<std::size_t>(i)] = source.bilinear(u, v);
  }
}

Heightfield resample_bilinear(const Heightfield& source, const Domain& target) {
  Heightfield out(target);
  for (int j = 0; j < target.height(); ++j) resample_bilinear_row(source, target, j, out.row(j));
  return out;
}

}  // namespace orogen
