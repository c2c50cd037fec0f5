#include "nodes/erosion/thermal.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

namespace orogen::erosion {
namespace {

constexpr float kWall = 1e30f;  // padding height: never lower than a cell, so nothing flows out of the grid

}  // namespace

ErosionMaps thermal_erosion(const Heightfield& in, const ThermalParams& p, const Heightfield* mask,
                            const Heightfield* hardness, const ExecContext* ctx, int* iterations_run) {
  const int w = in.width(), h = in.height();
  const int pw = w + 2;
  const std::size_t pn = static_cast<std::size_t>(pw) * static_cast<std::size_t>(h + 2);
  const double dx = in.domain.spacing.x, dy = in.domain.spacing.y;
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

  const double min_spacing = std::min(dx, dy);
  const int iterations = std::max(1, static_cast<int>(std::ceil(2.0 * p.travel_distance / min_spacing)));
  int it = 0;
  for (; it < iterations; ++it) {
    check_cancelled(ctx);
    // Pass 1: each cell's outflow ratio: it moves strength x half its largest excess, split over the lower
    // neighbours in proportion to their excess.
    tbb::parallel_for(tbb::blocked_range<int>(1, h + 1, 16), [&](const tbb::blocked_range<int>& r) {
      for (int j = r.begin(); j != r.end(); ++j) {
        const std::size_t q0 = static_cast<std::size_t>(j) * pw;
        for (int i = 1; i <= w; ++i) {
          const std::size_t q = q0 + static_cast<std::size_t>(i);
          const float zc = z[q];
          const float s = hardness ? tan_cell[q] / static_cast<float>(tan_t) : 1.0f;
          float sum = 0.0f, mx = 0.0f;
          for (int n = 0; n < 8; ++n) {
            const float e = zc - z[q + off[n]] - tal[n] * s;
            if (e > 0.0f) {
              sum += e;
              mx = std::max(mx, e);
            }
          }
          ratio[q] = sum > 0.0f ? rate[q] * 0.5f * mx / sum : 0.0f;
        }
      }
    });
    // Pass 2: each cell loses what it sends and gains what its higher neighbours send it, computed with the
    // same expression as the sender's.
    const float change = tbb::parallel_reduce(
        tbb::blocked_range<int>(1, h + 1, 16), 0.0f,
        [&](const tbb::blocked_range<int>& r, float acc) {
          for (int j = r.begin(); j != r.end(); ++j) {
            const std::size_t q0 = static_cast<std::size_t>(j) * pw;
            for (int i = 1; i <= w; ++i) {
              const std::size_t q = q0 + static_cast<std::size_t>(i);
              const float zc = z[q];
              const float sc = hardness ? tan_cell[q] / static_cast<float>(tan_t) : 1.0f;
              float out = 0.0f, gain = 0.0f;
              const float rc = ratio[q];
              for (int n = 0; n < 8; ++n) {
                const std::size_t nb = q + off[n];
                const float zn = z[nb];
                const float e_out = zc - zn - tal[n] * sc;
                if (e_out > 0.0f) out += rc * e_out;
                // Neighbour nb sends along the opposite direction (same distance, same talus index n).
                const float sn = hardness ? tan_cell[nb] / static_cast<float>(tan_t) : 1.0f;
                const float e_in = zn - zc - tal[n] * sn;
                if (e_in > 0.0f) gain += ratio[nb] * e_in;
              }
              z2[q] = zc - out + gain;
              moved[q] += out;
              acc = std::max(acc, std::max(out, gain));
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
