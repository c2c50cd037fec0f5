#include "nodes/erosion/thermal.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "nodes/common/finite_inputs.h"
#include "nodes/common/work_bounds.h"

namespace orogen::erosion {
namespace {

constexpr float kWall = 1e30f;  // padding height: never lower than a cell, so nothing flows out of the grid

// One row's excess over the talus towards neighbour row zn (talus tn, times the hardness scale sc when
// kScaled: without a hardness field the products by 1 are left out), summed and maximised per cell.
template <bool kScaled>
void excess_row(int w, const float* zr, const float* zn, float tn, const float* sc, float* __restrict sum,
                float* __restrict mx) {
  for (int i = 0; i < w; ++i) {
    const float e = std::max(0.0f, zr[i] - zn[i] - (kScaled ? tn * sc[i] : tn));
    sum[i] += e;
    mx[i] = std::max(mx[i], e);
  }
}

// One row's exchange with neighbour row zn: what each cell sends it (ratio rc, scale sc) and what it sends
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

ErosionMaps thermal_erosion(const Heightfield& in, const ThermalParams& p, const Heightfield* mask,
                            const Heightfield* hardness, const ExecContext* ctx, int* iterations_run) {
  require_finite_inputs("ThermalErosion", {{"in", &in}, {"mask", mask}, {"hardness", hardness}});
  const int w = in.width(), h = in.height();
  const int pw = w + 2;
  const std::size_t pn = static_cast<std::size_t>(pw) * static_cast<std::size_t>(h + 2);
  const double dx = in.domain.spacing.x, dy = in.domain.spacing.y;
  const double min_spacing = std::min(dx, dy);
  // Each iteration moves material about half a cell: the travel distance sets the count (checked: a long
  // travel on a fine grid does not fit an int, and a plan beyond the per-node ceiling is refused up front).
  const auto iterations = static_cast<int>(checked_count(2.0 * p.travel_distance / min_spacing,
                                                         "iterations (2 x travel_distance / grid spacing)",
                                                         "lower travel_distance or use a coarser grid"));
  check_work(static_cast<double>(iterations) * w * h, "ThermalErosion (iterations x samples)",
             "lower travel_distance or use a coarser grid");
  const double tan_t = std::tan(std::clamp(p.talus_angle, 0.01, 89.0) * M_PI / 180.0);
  // Per-cell tangent of the talus angle (hardness steepens it) times the neighbour distances.
  std::vector<float> tan_cell(hardness ? pn : 0, 0.0f);
  std::vector<float> rate(pn, 0.0f);  // strength x mask, 0 on the padding
  std::vector<float> z(pn, kWall), z2(pn, kWall), ratio(pn, 0.0f), moved(pn, 0.0f);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const std::size_t k = in.index(i, j);
      const std::size_t q = static_cast<std::size_t>(j + 1) * pw + static_cast<std::size_t>(i + 1);
      z[q] = in.data[k];
      rate[q] = static_cast<float>(std::clamp(p.strength, 0.0, 1.0)) * mask_at(mask, k);
      if (hardness) {
        const double hv = std::clamp(static_cast<double>(hardness->data[k]), 0.0, 1.0);
        const double ang = std::clamp(p.talus_angle, 0.01, 89.0);
        tan_cell[q] = static_cast<float>(std::tan((ang + hv * (89.0 - ang)) * M_PI / 180.0));
      }
    }
  z2 = z;
  const double diag = std::sqrt(dx * dx + dy * dy);
  const long off[8] = {-1, 1, -pw, pw, -pw - 1, -pw + 1, pw - 1, pw + 1};
  const double dist[8] = {dx, dx, dy, dy, diag, diag, diag, diag};
  float tal[8];
  for (int n = 0; n < 8; ++n) tal[n] = static_cast<float>(tan_t * dist[n]);

  int it = 0;
  for (; it < iterations; ++it) {
    check_cancelled(ctx);
    // Pass 1: each cell's outflow ratio: it moves strength x half its largest excess, split over the lower
    // neighbours in proportion to their excess. Loops run neighbour by neighbour along a row (vectorisable).
    tbb::parallel_for(tbb::blocked_range<int>(1, h + 1, 16), [&](const tbb::blocked_range<int>& r) {
      std::vector<float> sum(static_cast<std::size_t>(w)), mx(static_cast<std::size_t>(w)),
          sc(static_cast<std::size_t>(w), 1.0f);
      for (int j = r.begin(); j != r.end(); ++j) {
        const std::size_t q0 = static_cast<std::size_t>(j) * pw + 1;
        const float* zr = z.data() + q0;
        if (hardness)
          for (int i = 0; i < w; ++i) sc[i] = tan_cell[q0 + i] / static_cast<float>(tan_t);
        std::fill(sum.begin(), sum.end(), 0.0f);
        std::fill(mx.begin(), mx.end(), 0.0f);
        for (int n = 0; n < 8; ++n) {
          const float* zn = zr + off[n];
          const float tn = tal[n];
          if (hardness)
            excess_row<true>(w, zr, zn, tn, sc.data(), sum.data(), mx.data());
          else
            excess_row<false>(w, zr, zn, tn, sc.data(), sum.data(), mx.data());
        }
        float* ra = ratio.data() + q0;
        const float* rt = rate.data() + q0;
        for (int i = 0; i < w; ++i) ra[i] = sum[i] > 0.0f ? rt[i] * 0.5f * mx[i] / sum[i] : 0.0f;
      }
    });
    // Pass 2: each cell loses what it sends and gains what its higher neighbours send it, computed with the
    // same expression as the sender's.
    const float change = tbb::parallel_reduce(
        tbb::blocked_range<int>(1, h + 1, 16), 0.0f,
        [&](const tbb::blocked_range<int>& r, float acc) {
          std::vector<float> out(static_cast<std::size_t>(w)), gain(static_cast<std::size_t>(w));
          std::vector<float> sc(static_cast<std::size_t>(w), 1.0f), sn(static_cast<std::size_t>(w), 1.0f);
          for (int j = r.begin(); j != r.end(); ++j) {
            const std::size_t q0 = static_cast<std::size_t>(j) * pw + 1;
            const float* zr = z.data() + q0;
            const float* rc = ratio.data() + q0;
            if (hardness)
              for (int i = 0; i < w; ++i) sc[i] = tan_cell[q0 + i] / static_cast<float>(tan_t);
            std::fill(out.begin(), out.end(), 0.0f);
            std::fill(gain.begin(), gain.end(), 0.0f);
            for (int n = 0; n < 8; ++n) {
              const float* zn = zr + off[n];
              const float* rn = rc + off[n];
              const float tn = tal[n];
              // Neighbour nb sends along the opposite direction (same distance, same talus index n).
              if (hardness) {
                for (int i = 0; i < w; ++i) sn[i] = tan_cell[q0 + i + off[n]] / static_cast<float>(tan_t);
                transfer_row<true>(w, zr, zn, rc, rn, tn, sc.data(), sn.data(), out.data(), gain.data());
              } else {
                transfer_row<false>(w, zr, zn, rc, rn, tn, sc.data(), sn.data(), out.data(), gain.data());
              }
            }
            float* z2r = z2.data() + q0;
            float* mv = moved.data() + q0;
            for (int i = 0; i < w; ++i) {
              z2r[i] = zr[i] - out[i] + gain[i];
              mv[i] += out[i];
              acc = std::max(acc, std::max(out[i], gain[i]));
            }
          }
          return acc;
        },
        [](float a, float b) { return std::max(a, b); });
    std::swap(z, z2);
    report(ctx, static_cast<double>(it + 1) / iterations);
    if (change <= p.tolerance) {
      ++it;
      break;
    }
  }
  if (iterations_run) *iterations_run = it;

  ErosionMaps maps;
  maps.out = std::make_shared<Heightfield>(in.domain);
  maps.flow = std::make_shared<Heightfield>(in.domain);
  float mmax = 0.0f;
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const std::size_t q = static_cast<std::size_t>(j + 1) * pw + static_cast<std::size_t>(i + 1);
      maps.out->at(i, j) = z[q];
      mmax = std::max(mmax, moved[q]);
    }
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const std::size_t q = static_cast<std::size_t>(j + 1) * pw + static_cast<std::size_t>(i + 1);
      maps.flow->at(i, j) = mmax > 0.0f ? moved[q] / mmax : 0.0f;
    }
  fill_change_maps(in, maps, ctx);
  return maps;
}

}  // namespace orogen::erosion
