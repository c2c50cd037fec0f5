#include "nodes/hydrology/water_flow_step.h"

#include <algorithm>

#include "nodes/hydrology/flow_routing.h"

namespace orogen::hydrology {

WaterFlowGrid::WaterFlowGrid(int width, int height, double cell_area, const float* heights)
    : nx(width), ny(height), area(cell_area), z(heights) {
  const std::size_t n = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  w.assign(n, 0.0), next.assign(n, 0.0), out.assign(n, 0.0), scale.assign(n, 0.0), flux.assign(n, 0.0);
  drain.assign(n, kNoDrain);
}

// Each wet cell sends min(w, largest surface drop / 2) to its lower neighbors (on the water surface), in proportion
// to the drops.
void water_spread_row(WaterFlowGrid& g, int j, int x0, int x1, int s0, int s1, ExactDoubleSum& moved) {
  const double* w = g.w.data();
  const float* z = g.z;
  for (int i = x0; i < x1; ++i) {
    const std::size_t c = g.at(i, j);
    g.out[c] = g.scale[c] = 0.0;
    if (!(w[c] > 0.0)) continue;
    const double s = z[c] + w[c];
    double dmax = 0.0, dsum = 0.0;
    for (int k = 0; k < 8; ++k) {
      const int ni = i + kDi[k], nj = j + kDj[k];
      if (ni < 0 || nj < 0 || ni >= g.nx || nj >= g.ny) continue;
      const std::size_t m = g.at(ni, nj);
      const double d = s - (z[m] + w[m]);
      if (d > 0.0) {
        dmax = std::max(dmax, d);
        dsum += d;
      }
    }
    if (dsum > 0.0) {
      g.out[c] = std::min(w[c], 0.5 * dmax);
      g.scale[c] = g.out[c] / dsum;
      if (i >= s0 && i < s1) moved.add(g.out[c]);
    }
  }
}

// What the neighbors send, from the same drops they computed, so each row is independent.
void water_gather_row(WaterFlowGrid& g, int j, int x0, int x1) {
  const double* w = g.w.data();
  const float* z = g.z;
  for (int i = x0; i < x1; ++i) {
    const std::size_t c = g.at(i, j);
    const double s = z[c] + w[c];
    double gain = 0.0;
    for (int k = 0; k < 8; ++k) {
      const int ni = i + kDi[k], nj = j + kDj[k];
      if (ni < 0 || nj < 0 || ni >= g.nx || nj >= g.ny) continue;
      const std::size_t m = g.at(ni, nj);
      if (g.scale[m] == 0.0) continue;
      const double d = (z[m] + w[m]) - s;
      if (d > 0.0) gain += g.scale[m] * d;
    }
    g.next[c] = w[c] - g.out[c] + gain;
    g.flux[c] += g.out[c] * g.area;
  }
}

}  // namespace orogen::hydrology
