#include "nodes/noise/worley_neighbourhood.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace orogen::noise {

double worley_metric(WorleyMetric metric, double ax, double ay) {
  switch (metric) {
    case WorleyMetric::Euclidean:
      return std::sqrt(ax * ax + ay * ay);
    case WorleyMetric::Manhattan:
      return ax + ay;
    case WorleyMetric::Chebyshev:
      return std::max(ax, ay);
  }
  return 0.0;
}

namespace {

// Lower bound of |point - sample| on one axis for the cell at offset d (see the header).
double axis_gap(int d, double half_jitter) {
  if (d == 0) return 0.0;
  if (d > 0) return std::max(0.0, d - 0.5 - half_jitter);
  return std::max(0.0, -d - half_jitter);
}

}  // namespace

WorleyNeighbourhood worley_neighbourhood(WorleyMetric metric, float jitter, int rank) {
  if (rank < 1 || rank > 4) throw std::invalid_argument("worley_neighbourhood: rank must be 1..4");
  if (!(jitter >= 0.0f && jitter <= 1.0f))
    throw std::invalid_argument("worley_neighbourhood: jitter must be in [0, 1]");
  // Work with the jitter as the kernel will see it (a float), widened exactly.
  const double J = static_cast<double>(jitter) * 0.5;
  const double a = 0.5 + J, b = 1.0 + J;
  double bound = 0.0;
  switch (rank) {
    case 1:
      bound = worley_metric(metric, a, a);
      break;
    case 2:
    case 3:
      bound = worley_metric(metric, b, a);
      break;
    default:
      bound = worley_metric(metric, b, b);
      break;
  }
  // Every metric here is >= the largest per-axis distance, so an axis offset whose gap alone reaches the
  // bound is out whatever the other axis: that bounds the scan.
  const int reach = static_cast<int>(std::ceil(bound + J)) + 2;
  WorleyNeighbourhood n;
  for (int dy = -reach; dy <= reach; ++dy) {
    for (int dx = -reach; dx <= reach; ++dx) {
      if (worley_metric(metric, axis_gap(dx, J), axis_gap(dy, J)) < bound) {
        n.dx.push_back(dx);
        n.dy.push_back(dy);
      }
    }
  }
  return n;
}

}  // namespace orogen::noise
