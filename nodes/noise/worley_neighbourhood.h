#pragma once
// The cells a Worley evaluation must visit to be exact, for a metric, a jitter and the number k of nearest
// distances wanted (F1..Fk).
//
// Feature points: one per lattice cell; cell (X, Y) holds the point
//   (X + 0.5 + jitter * (r_x - 0.5), Y + 0.5 + jitter * (r_y - 0.5)),  r_x, r_y in [0, 1),
// so on each axis a cell's point lies within the closed interval [X + 0.5 - J, X + 0.5 + J], J = jitter / 2.
//
// The search frame. By the mirror symmetry of that interval about the cell centre, a sample with
// fraction f < 1/2 on an axis is the mirror of one with fraction 1 - f > 1/2 and the cell offsets mirror
// with it. The kernel therefore mirrors the offsets per sample and per axis, and the proof only has to
// cover fractions f in [1/2, 1] on both axes.
//
// Upper bounds on F_k (k-th smallest distance), with a = 1/2 + J and b = 1 + J, from k known points:
//   own cell (0, 0): |x - f| <= max(f - (1/2 - J), (1/2 + J) - f) <= a on each axis.
//   cell (1, 0):     x in [3/2 - J, 3/2 + J], so |x - f| <= 3/2 + J - 1/2 = b on x and <= a on y.
//   cells (0, 1), (1, 1) likewise.
//   F1 <= M(a, a);  F2 <= M(b, a) (two points within it);  F3 <= M(b, a) ((0,0), (1,0), (0,1));
//   F4 <= M(b, b) (all four), where M is the metric of the per-axis distances (monotone in each).
// Lower bound on the distance to any point of the cell at offset d on one axis:
//   d = 0:  0;   d >= 1:  x >= d + 1/2 - J and f <= 1, so x - f >= d - 1/2 - J;
//   d <= -1: x <= d + 1/2 + J and f >= 1/2, so f - x >= |d| - J.   (clamped at 0)
// A cell whose lower bound M(g_x, g_y) is >= the bound on F_k cannot hold a point strictly closer than F_k,
// so leaving it out does not change F1..Fk. The list keeps every other cell; it is finite because the
// per-axis bound grows with |d|. The tests compare the result with a brute-force search over all points.
#include <cstdint>
#include <vector>

#include "nodes/noise/noise_types.h"

namespace orogen::noise {

struct WorleyNeighbourhood {
  std::vector<std::int32_t> dx, dy;  // cell offsets in the mirrored frame (sample in the upper half)
  int size() const { return static_cast<int>(dx.size()); }
};

// Offsets needed for exact F1..F_rank (rank 1, 2, 3 or 4) under `metric` with `jitter` in [0, 1].
WorleyNeighbourhood worley_neighbourhood(WorleyMetric metric, float jitter, int rank);

// The metric of per-axis distances (|dx|, |dy|); Euclidean returns the true distance (not squared).
double worley_metric(WorleyMetric metric, double ax, double ay);

}  // namespace orogen::noise
