#include "nodes/erosion/thermal_step.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "nodes/common/work_bounds.h"

namespace orogen::erosion {
namespace {

// One row's excess over the talus towards neighbor row zn (talus tn, times the hardness scale sc when
// kScaled: without a hardness field the products by 1 are left out), summed and maximized per cell.
template <bool kScaled>
void excess_row(int w, const float* zr, const float* zn, float tn, const float* sc, float* __restrict sum,
                float* __restrict mx) {
  for (int i = 0; i < w; ++i) {
    const float e = std::max(0.0f, zr[i] - zn[i] - (kScaled ? tn * sc[i] : tn));
    sum[i] += e;
    mx[i] = std::max(mx[i], e);
  }
}

// One row's exchange with neighbor row zn: what each cell sends it (ratio rc, scale sc) and what it sends
// back along the opposite direction (ratio rn, scale sn), with the sender's own expression (zn - zr is
// exactly -(zr - zn)).
template <bool kScaled>
void transfer_row(int w, const float* zr, const float* zn, const float* rc, const float* rn, float tn, const float* sc,
                  const float* sn, float* __restrict out, float* __restrict gain) {
  for (int i = 0; i < w; ++i) {
    const float d = zr[i] - zn[i];
    out[i] += rc[i] * std::max(0.0f, d - (kScaled ? tn * sc[i] : tn));
    gain[i] += rn[i] * std::max(0.0f, -d - (kScaled ? tn * sn[i] : tn));
  }
}

}  // namespace

ThermalStencil thermal_stencil(const ThermalParams& p, glm::dvec2 spacing, glm::ivec2 resolution) {
  ThermalStencil s;
  const double dx = spacing.x, dy = spacing.y;
  // Each iteration moves material about half a cell: the travel distance sets the count (checked: a long
  // travel on a fine grid does not fit an int, and a plan beyond the per-node ceiling is refused up front).
  s.iterations = static_cast<int>(checked_count(2.0 * p.travel_distance / std::min(dx, dy),
                                                "iterations (2 x travel_distance / grid spacing)",
                                                "lower travel_distance or use a coarser grid"));
  check_work(static_cast<double>(s.iterations) * resolution.x * resolution.y, "ThermalErosion (iterations x samples)",
             "lower travel_distance or use a coarser grid");
  s.tan_t = std::tan(std::clamp(p.talus_angle, 0.01, 89.0) * M_PI / 180.0);
  const double diag = std::sqrt(dx * dx + dy * dy);
  const double dist[8] = {dx, dx, dy, dy, diag, diag, diag, diag};
  for (int n = 0; n < 8; ++n) s.tal[n] = static_cast<float>(s.tan_t * dist[n]);
  return s;
}

float thermal_rate(const ThermalParams& p, float mask) {
  return static_cast<float>(std::clamp(p.strength, 0.0, 1.0)) * std::clamp(mask, 0.0f, 1.0f);
}

float thermal_tangent(const ThermalParams& p, float hardness) {
  const double hv = std::clamp(static_cast<double>(hardness), 0.0, 1.0);
  const double ang = std::clamp(p.talus_angle, 0.01, 89.0);
  return static_cast<float>(std::tan((ang + hv * (89.0 - ang)) * M_PI / 180.0));
}

ThermalGrids::ThermalGrids(int pitch_, int rows, bool hardness) : pitch(pitch_) {
  const std::size_t n = static_cast<std::size_t>(pitch) * static_cast<std::size_t>(rows);
  z.assign(n, kThermalWall);
  z2.assign(n, kThermalWall);
  rate.assign(n, 0.0f);
  tan_cell.assign(hardness ? n : 0, 0.0f);
  ratio.assign(n, 0.0f);
  moved.assign(n, 0.0f);
}

float thermal_iteration(ThermalGrids& g, const ThermalStencil& s, GridWindow heights, GridWindow ratios) {
  const bool hardness = !g.tan_cell.empty();
  const long pw = g.pitch;
  const long off[8] = {-1, 1, -pw, pw, -pw - 1, -pw + 1, pw - 1, pw + 1};
  const auto tan_t = static_cast<float>(s.tan_t);
  // Pass 1: each cell's outflow ratio: it moves strength x half its largest excess, split over the lower
  // neighbors in proportion to their excess. Loops run neighbor by neighbor along a row (vectorizable).
  const int rw = ratios.x1 - ratios.x0;
  tbb::parallel_for(tbb::blocked_range<int>(ratios.y0, ratios.y1, 16), [&](const tbb::blocked_range<int>& r) {
    std::vector<float> sum(static_cast<std::size_t>(rw)), mx(static_cast<std::size_t>(rw)),
        sc(static_cast<std::size_t>(rw), 1.0f);
    for (int j = r.begin(); j != r.end(); ++j) {
      const std::size_t q0 = g.at(ratios.x0, j);
      const float* zr = g.z.data() + q0;
      if (hardness)
        for (int i = 0; i < rw; ++i) sc[i] = g.tan_cell[q0 + i] / tan_t;
      std::fill(sum.begin(), sum.end(), 0.0f);
      std::fill(mx.begin(), mx.end(), 0.0f);
      for (int n = 0; n < 8; ++n) {
        const float* zn = zr + off[n];
        if (hardness)
          excess_row<true>(rw, zr, zn, s.tal[n], sc.data(), sum.data(), mx.data());
        else
          excess_row<false>(rw, zr, zn, s.tal[n], sc.data(), sum.data(), mx.data());
      }
      float* ra = g.ratio.data() + q0;
      const float* rt = g.rate.data() + q0;
      for (int i = 0; i < rw; ++i) ra[i] = sum[i] > 0.0f ? rt[i] * 0.5f * mx[i] / sum[i] : 0.0f;
    }
  });
  // Pass 2: each cell loses what it sends and gains what its higher neighbors send it, computed with the
  // same expression as the sender's.
  const int w = heights.x1 - heights.x0;
  const float change = tbb::parallel_reduce(
      tbb::blocked_range<int>(heights.y0, heights.y1, 16), 0.0f,
      [&](const tbb::blocked_range<int>& r, float acc) {
        std::vector<float> out(static_cast<std::size_t>(w)), gain(static_cast<std::size_t>(w));
        std::vector<float> sc(static_cast<std::size_t>(w), 1.0f), sn(static_cast<std::size_t>(w), 1.0f);
        for (int j = r.begin(); j != r.end(); ++j) {
          const std::size_t q0 = g.at(heights.x0, j);
          const float* zr = g.z.data() + q0;
          const float* rc = g.ratio.data() + q0;
          if (hardness)
            for (int i = 0; i < w; ++i) sc[i] = g.tan_cell[q0 + i] / tan_t;
          std::fill(out.begin(), out.end(), 0.0f);
          std::fill(gain.begin(), gain.end(), 0.0f);
          for (int n = 0; n < 8; ++n) {
            const float* zn = zr + off[n];
            const float* rn = rc + off[n];
            // Neighbor nb sends along the opposite direction (same distance, same talus index n).
            if (hardness) {
              for (int i = 0; i < w; ++i) sn[i] = g.tan_cell[q0 + i + off[n]] / tan_t;
              transfer_row<true>(w, zr, zn, rc, rn, s.tal[n], sc.data(), sn.data(), out.data(), gain.data());
            } else {
              transfer_row<false>(w, zr, zn, rc, rn, s.tal[n], sc.data(), sn.data(), out.data(), gain.data());
            }
          }
          float* z2r = g.z2.data() + q0;
          float* mv = g.moved.data() + q0;
          for (int i = 0; i < w; ++i) {
            z2r[i] = zr[i] - out[i] + gain[i];
            mv[i] += out[i];
            acc = std::max(acc, std::max(out[i], gain[i]));
          }
        }
        return acc;
      },
      [](float a, float b) { return std::max(a, b); });
  std::swap(g.z, g.z2);
  return change;
}

}  // namespace orogen::erosion
