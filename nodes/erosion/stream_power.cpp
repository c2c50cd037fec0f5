#include "nodes/erosion/stream_power.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <queue>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace orogen::erosion {
namespace {

constexpr int kDi[8] = {-1, 1, 0, 0, -1, 1, -1, 1};
constexpr int kDj[8] = {0, 0, -1, 1, -1, -1, 1, 1};

// The smallest increment that still orders the filled surface: relative to the height so that it survives
// double rounding, and far below any real relief.
inline double raise(double z) { return z + std::max(1e-9, std::abs(z) * 1e-12); }

template <class Fn>
void rows(int h, Fn&& fn) {
  tbb::parallel_for(tbb::blocked_range<int>(0, h, 8), [&](const tbb::blocked_range<int>& r) {
    for (int j = r.begin(); j != r.end(); ++j) fn(j);
  });
}

}  // namespace

void route(const std::vector<double>& z, int w, int h, double dx, double dy, const std::vector<unsigned char>& outlet,
           Routing& r) {
  const std::size_t n = z.size();
  r.filled.assign(n, 0.0);
  r.receiver.assign(n, -1);
  std::vector<std::int32_t> parent(n, -1);
  std::vector<unsigned char> closed(n, 0);
  // Priority flood with epsilon (Barnes, Lehman and Mulla 2014): from the outlets inward, every cell is
  // raised to just above the cell it was reached from if it lies lower, so every cell drains.
  using Item = std::pair<double, std::int32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  std::deque<std::int32_t> pit;
  for (std::size_t k = 0; k < n; ++k)
    if (outlet[k]) {
      closed[k] = 1;
      r.filled[k] = z[k];
      open.push({z[k], static_cast<std::int32_t>(k)});
    }
  while (!open.empty() || !pit.empty()) {
    std::int32_t c;
    if (!pit.empty()) {
      c = pit.front();
      pit.pop_front();
    } else {
      c = open.top().second;
      open.pop();
    }
    const int ci = c % w, cj = c / w;
    for (int q = 0; q < 8; ++q) {
      const int i = ci + kDi[q], j = cj + kDj[q];
      if (i < 0 || i >= w || j < 0 || j >= h) continue;
      const std::int32_t nb = j * w + i;
      if (closed[nb]) continue;
      closed[nb] = 1;
      parent[nb] = c;
      const double lift = raise(r.filled[c]);
      if (z[nb] <= lift) {
        r.filled[nb] = lift;
        pit.push_back(nb);
      } else {
        r.filled[nb] = z[nb];
        open.push({z[nb], nb});
      }
    }
  }
  // D8 steepest descent on the filled surface.
  const double diag = std::sqrt(dx * dx + dy * dy);
  const double dist[8] = {dx, dx, dy, dy, diag, diag, diag, diag};
  rows(h, [&](int j) {
    for (int i = 0; i < w; ++i) {
      const std::int32_t k = j * w + i;
      if (outlet[k]) {
        r.receiver[k] = k;
        continue;
      }
      double best = 0.0;
      std::int32_t rec = -1;
      for (int q = 0; q < 8; ++q) {
        const int ii = i + kDi[q], jj = j + kDj[q];
        if (ii < 0 || ii >= w || jj < 0 || jj >= h) continue;
        const std::int32_t nb = jj * w + ii;
        const double s = (r.filled[k] - r.filled[nb]) / dist[q];
        if (s > best) best = s, rec = nb;
      }
      r.receiver[k] = rec >= 0 ? rec : (parent[k] >= 0 ? parent[k] : k);
    }
  });
  // Donors (CSR) and the stack: outlets first, then breadth-first upstream.
  std::vector<std::int32_t> count(n + 1, 0), donors(n);
  for (std::size_t k = 0; k < n; ++k)
    if (r.receiver[k] != static_cast<std::int32_t>(k)) ++count[static_cast<std::size_t>(r.receiver[k]) + 1];
  for (std::size_t k = 0; k < n; ++k) count[k + 1] += count[k];
  {
    std::vector<std::int32_t> fill(count.begin(), count.end() - 1);
    for (std::size_t k = 0; k < n; ++k)
      if (r.receiver[k] != static_cast<std::int32_t>(k)) donors[fill[r.receiver[k]]++] = static_cast<std::int32_t>(k);
  }
  r.stack.clear();
  r.stack.reserve(n);
  for (std::size_t k = 0; k < n; ++k)
    if (r.receiver[k] == static_cast<std::int32_t>(k)) r.stack.push_back(static_cast<std::int32_t>(k));
  for (std::size_t head = 0; head < r.stack.size(); ++head) {
    const std::int32_t c = r.stack[head];
    for (std::int32_t q = count[c]; q < count[c + 1]; ++q) r.stack.push_back(donors[q]);
  }
  // Drainage area, accumulated downstream.
  r.area.assign(n, dx * dy);
  for (std::size_t q = r.stack.size(); q-- > 0;) {
    const std::int32_t k = r.stack[q];
    if (r.receiver[k] != k) r.area[r.receiver[k]] += r.area[k];
  }
}

ErosionMaps stream_power(const Heightfield& in, const StreamPowerParams& p, const Heightfield* uplift,
                         const Heightfield* mask, const ExecContext* ctx, StreamPowerStats* stats,
                         const std::vector<unsigned char>* outlets, std::shared_ptr<Heightfield>* accumulation) {
  const int w = in.width(), h = in.height();
  const std::size_t n = in.data.size();
  const double dx = in.domain.spacing.x, dy = in.domain.spacing.y;
  const double diag = std::sqrt(dx * dx + dy * dy);
  // Fixed base level: the given outlets, else the border. Cells under sea level join them step by step
  // (uplift can lift the sea floor into land).
  std::vector<unsigned char> fixed(n, 0), outlet(n, 0);
  if (outlets) {
    fixed = *outlets;
  } else {
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) fixed[in.index(i, j)] = i == 0 || j == 0 || i == w - 1 || j == h - 1;
  }
  std::vector<double> z(in.data.begin(), in.data.end()), ero(n, 0.0), dep(n, 0.0), zprev(n), ztmp(n);
  std::vector<double> kfac(n), ufac(n);
  for (std::size_t k = 0; k < n; ++k) {
    kfac[k] = mask_at(mask, k);
    ufac[k] = fixed[k] ? 0.0 : p.uplift * (uplift ? std::max(0.0f, uplift->data[k]) : 1.0f);
  }
  const int steps = std::max(1, static_cast<int>(std::ceil(p.duration / p.dt - 1e-9)));
  const double dt = p.duration / steps;
  // Diffusion sub-steps: explicit FTCS is stable for D dt_sub (2/dx^2 + 2/dy^2) <= 1.
  const double dt_diff_max = 0.9 / (std::max(p.diffusion, 1e-30) * (2.0 / (dx * dx) + 2.0 / (dy * dy)));
  const int diff_steps = p.diffusion > 0 ? std::max(1, static_cast<int>(std::ceil(dt / dt_diff_max))) : 0;
  Routing r;
  StreamPowerStats st;
  for (int s = 0; s < steps; ++s) {
    check_cancelled(ctx);
    zprev = z;
    for (std::size_t k = 0; k < n; ++k) {
      z[k] += ufac[k] * dt;
      outlet[k] = fixed[k] || z[k] < p.sea_level;
    }
    route(z, w, h, dx, dy, outlet, r);
    for (std::size_t k = 0; k < n; ++k) {
      dep[k] += r.filled[k] - z[k];
      z[k] = r.filled[k];
    }
    // Implicit incision from the outlets upstream (receivers are already at t + dt).
    for (const std::int32_t k : r.stack) {
      const std::int32_t rc = r.receiver[k];
      if (rc == k) continue;
      const double len = (k % w != rc % w && k / w != rc / w) ? diag : (k % w != rc % w ? dx : dy);
      const double f = p.k * kfac[k] * dt * std::pow(r.area[k], p.m) / std::pow(len, p.n);
      const double z0 = z[k], zr = z[rc];
      double zn = z0;
      if (z0 > zr && f > 0) {
        if (p.n == 1.0) {
          zn = (z0 + f * zr) / (1.0 + f);
        } else {
          // Newton on g(z) = z - z0 + f (z - zr)^n over (zr, z0], safeguarded by bisection.
          double lo = zr, hi = z0;
          zn = z0;
          for (int it = 0; it < 50; ++it) {
            const double d = zn - zr;
            const double g = zn - z0 + f * std::pow(d, p.n);
            if (g > 0) hi = zn; else lo = zn;
            const double gp = 1.0 + f * p.n * std::pow(d, p.n - 1.0);
            double next = zn - g / gp;
            if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
            if (std::abs(next - zn) <= 1e-12 * std::max(1.0, std::abs(zn))) {
              zn = next;
              break;
            }
            zn = next;
          }
        }
      }
      ero[k] += z0 - zn;
      z[k] = zn;
    }
    // Hillslope diffusion, base level fixed.
    for (int sd = 0; sd < diff_steps; ++sd) {
      const double c = p.diffusion * dt / diff_steps;
      rows(h, [&](int j) {
        for (int i = 0; i < w; ++i) {
          const std::size_t k = static_cast<std::size_t>(j) * w + i;
          if (outlet[k]) {
            ztmp[k] = z[k];
            continue;
          }
          const double zc = z[k];
          const double lx = (z[i > 0 ? k - 1 : k] + z[i < w - 1 ? k + 1 : k] - 2 * zc) / (dx * dx);
          const double ly = (z[j > 0 ? k - w : k] + z[j < h - 1 ? k + w : k] - 2 * zc) / (dy * dy);
          const double dz = c * kfac[k] * (lx + ly);
          ztmp[k] = zc + dz;
          (dz < 0 ? ero[k] : dep[k]) += std::abs(dz);
        }
      });
      std::swap(z, ztmp);
    }
    double mx = 0;
    for (std::size_t k = 0; k < n; ++k)
      if (!outlet[k]) mx = std::max(mx, std::abs(z[k] - zprev[k]) / dt);
    st.max_change_last_step = mx;
    report(ctx, static_cast<double>(s + 1) / steps);
  }
  st.steps = steps;
  if (stats) *stats = st;

  ErosionMaps maps;
  maps.out = std::make_shared<Heightfield>(in.domain);
  maps.erosion = std::make_shared<Heightfield>(in.domain);
  maps.deposition = std::make_shared<Heightfield>(in.domain);
  maps.flow = std::make_shared<Heightfield>(in.domain);
  double amax = dx * dy;
  for (double a : r.area) amax = std::max(amax, a);
  const double lmax = std::log(amax / (dx * dy));
  for (std::size_t k = 0; k < n; ++k) {
    maps.out->data[k] = static_cast<float>(z[k]);
    maps.erosion->data[k] = static_cast<float>(ero[k]);
    maps.deposition->data[k] = static_cast<float>(dep[k]);
    maps.flow->data[k] = lmax > 0 && !r.area.empty() ? static_cast<float>(std::log(r.area[k] / (dx * dy)) / lmax) : 0.0f;
  }
  if (accumulation) {
    *accumulation = std::make_shared<Heightfield>(in.domain);
    for (std::size_t k = 0; k < n; ++k) (*accumulation)->data[k] = static_cast<float>(r.area.empty() ? dx * dy : r.area[k]);
  }
  return maps;
}

}  // namespace orogen::erosion
