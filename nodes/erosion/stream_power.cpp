#include "nodes/erosion/stream_power.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <queue>
#include <vector>

#include "nodes/common/cancellable_rows.h"
#include "nodes/hydrology/basin_graph.h"
#include "nodes/hydrology/flow_routing.h"

namespace orogen::erosion {
namespace {

constexpr int kDi[8] = {-1, 1, 0, 0, -1, 1, -1, 1};
constexpr int kDj[8] = {0, 0, -1, 1, -1, -1, 1, 1};

// The smallest increment that still orders the filled surface: relative to the height so that it survives
// double rounding, and far below any real relief.
inline double raise(double z) { return z + std::max(1e-9, std::abs(z) * 1e-12); }

}  // namespace

ErosionMaps stream_power(const Heightfield& in, const StreamPowerParams& p, const Heightfield* uplift,
                         const Heightfield* mask, const ExecContext* ctx, StreamPowerStats* stats,
                         const std::vector<unsigned char>* outlets, std::shared_ptr<Heightfield>* accumulation) {
  const int w = in.width(), h = in.height();
  const std::size_t n = in.data.size();
  const double dx = in.domain.spacing.x, dy = in.domain.spacing.y;
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
  const hydrology::FlowGrid grid = hydrology::FlowGrid::of(in.domain);
  const bool basin_graph = p.depressions == StreamPowerParams::Depressions::BasinGraph;
  std::vector<float> zf, zround;
  hydrology::D8Flow flow;
  hydrology::BasinRouting routing;
  std::vector<std::int32_t> order;
  std::vector<double> area;
  std::vector<double> row_max(static_cast<std::size_t>(h)), row_sum(static_cast<std::size_t>(h));
  std::vector<std::size_t> row_count(static_cast<std::size_t>(h));
  StreamPowerStats st;
  // Implicit incision of cell k towards its receiver (already at t + dt).
  // A^m by table for areas of up to kTable whole cells (exactly count x cell area, as the unweighted
  // accumulation gives): the same pow() values, computed once; L^n per direction.
  constexpr int kTable = 1 << 16;
  const double cell_area = grid.cell_area();
  std::vector<double> area_pow(kTable);
  for (int q = 0; q < kTable; ++q) area_pow[static_cast<std::size_t>(q)] = std::pow(q * cell_area, p.m);
  double len_pow[8];
  for (int q = 0; q < 8; ++q) len_pow[q] = std::pow(grid.distance(q), p.n);
  auto incise = [&](std::int32_t k, std::int32_t rc, int direction) {
    if (rc == k || area[k] < p.channel_area) return;
    const double a = area[k], cells = std::nearbyint(a / cell_area);
    const double am = cells < kTable && cells * cell_area == a ? area_pow[static_cast<std::size_t>(cells)] : std::pow(a, p.m);
    const double f = p.k * kfac[k] * dt * am / len_pow[direction];
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
  };
  hydrology::Outlets outs;
  outs.border = false;
  outs.mask = outlet;
  for (int s = 0; s < steps; ++s) {
    check_cancelled(ctx);
    for_each_row_unreported(ctx, h, [&](int j) {
      for (std::size_t k = static_cast<std::size_t>(j) * w, e = k + w; k < e; ++k) {
        zprev[k] = z[k];
        z[k] += ufac[k] * dt;
        outlet[k] = fixed[k] || z[k] < p.sea_level;
      }
    });
    // Hillslope diffusion, base level fixed, before the incision: the implicit sweep then cuts through
    // whatever diffusion laid into the channels within the same step, so river profiles stay clean.
    for (int sd = 0; sd < diff_steps; ++sd) {
      const double c = p.diffusion * dt / diff_steps;
      const double cx = 1.0 / (dx * dx), cy = 1.0 / (dy * dy);
      for_each_row_unreported(ctx, h, [&](int j) {
        auto cell = [&](int i, std::size_t k, double zw, double ze, double zs, double zn) {
          const double zc = z[k];
          const double lx = (zw + ze - 2 * zc) * cx;
          const double ly = (zs + zn - 2 * zc) * cy;
          const double dz = outlet[k] ? 0.0 : c * kfac[k] * (lx + ly);
          ztmp[k] = zc + dz;
          // Branch-free: adding +0.0 leaves a sum unchanged.
          ero[k] += std::max(-dz, 0.0);
          dep[k] += std::max(dz, 0.0);
          (void)i;
        };
        const std::size_t row = static_cast<std::size_t>(j) * w;
        const std::size_t up = j > 0 ? row - w : row, down = j < h - 1 ? row + w : row;
        if (w == 1) {
          cell(0, row, z[row], z[row], z[up], z[down]);
          return;
        }
        cell(0, row, z[row], z[row + 1], z[up], z[down]);
        for (int i = 1; i < w - 1; ++i) cell(i, row + i, z[row + i - 1], z[row + i + 1], z[up + i], z[down + i]);
        cell(w - 1, row + w - 1, z[row + w - 2], z[row + w - 1], z[up + w - 1], z[down + w - 1]);
      });
      std::swap(z, ztmp);
    }
    area.resize(n);
    if (basin_graph) {
      // Local D8 over the surface as it is; only the pits' basins are rerouted over their passes (basin
      // graph), then the lakes fill with sediment to just above the pass, one outlet tree per task.
      hydrology::route_basin_graph_fill(grid, z, outs, routing, dep, ctx);
      hydrology::accumulate_stack(grid, routing, area);
      const std::int32_t* rcv = routing.flow.receiver.data();
      const std::uint8_t* dir = routing.flow.direction.data();
      hydrology::for_each_tree(routing, [&](std::int32_t first, std::int32_t last) {
        for (std::int32_t q = first; q < last; ++q) {
          const std::int32_t k = routing.stack[static_cast<std::size_t>(q)];
          incise(k, rcv[k], dir[k]);
        }
      });
    } else {
      // Routing over the depression-filled surface with the hydrology core: closed depressions fill with
      // sediment (Priority-Flood+epsilon), then D8 receivers, the Braun-Willett stack and the drainage area.
      zf.resize(n);
      for (std::size_t k = 0; k < n; ++k) zf[k] = static_cast<float>(z[k]);
      zround = zf;
      hydrology::fill_depressions(grid, zf, hydrology::FlatMode::Epsilon, outs, ctx);
      for (std::size_t k = 0; k < n; ++k)
        if (zf[k] != zround[k]) {
          dep[k] += static_cast<double>(zf[k]) - z[k];
          z[k] = zf[k];
        }
      flow = hydrology::d8_flow(grid, zf, outs, ctx);
      order = hydrology::stack_order(grid, flow);
      area = hydrology::accumulate_d8(grid, flow, {}, ctx);
      // Implicit incision from the outlets upstream (receivers are already at t + dt).
      for (const std::int32_t k : order) incise(k, flow.receiver[k], flow.direction[k]);
    }
    for_each_row_unreported(ctx, h, [&](int j) {
      double mx = 0, sum = 0;
      std::size_t count = 0;
      for (std::size_t k = static_cast<std::size_t>(j) * w, e = k + w; k < e; ++k)
        if (!outlet[k]) {
          const double c = std::abs(z[k] - zprev[k]) / dt;
          mx = std::max(mx, c);
          sum += c;
          ++count;
        }
      row_max[static_cast<std::size_t>(j)] = mx;
      row_sum[static_cast<std::size_t>(j)] = sum;
      row_count[static_cast<std::size_t>(j)] = count;
    });
    double mx = 0, sum = 0;
    std::size_t count = 0;
    for (int j = 0; j < h; ++j) {
      mx = std::max(mx, row_max[static_cast<std::size_t>(j)]);
      sum += row_sum[static_cast<std::size_t>(j)];
      count += row_count[static_cast<std::size_t>(j)];
    }
    st.max_change_last_step = mx;
    st.mean_change_last_step = count ? sum / count : 0.0;
    report(ctx, static_cast<double>(s + 1) / steps);
  }
  st.steps = steps;
  if (stats) *stats = st;
  // The last diffusion sub-steps may leave shallow closed depressions on filled flats, and the result is
  // rounded to float: fill them in float like every step does, so the result drains (sediment settles in
  // them; recorded as deposition).
  zf.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    outlet[k] = fixed[k] || z[k] < p.sea_level;
    zf[k] = static_cast<float>(z[k]);
  }
  zround = zf;
  if (basin_graph) {
    // Route the float surface over its passes and fill its lakes one float step above the pass.
    hydrology::route_basin_graph_fill(grid, std::span<float>(zf), outs, routing, {}, ctx);
  } else {
    hydrology::fill_depressions(grid, zf, hydrology::FlatMode::Epsilon, outs, ctx);
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (zf[k] != zround[k]) dep[k] += static_cast<double>(zf[k]) - z[k];
    z[k] = zf[k];
  }

  ErosionMaps maps;
  maps.out = std::make_shared<Heightfield>(in.domain);
  maps.erosion = std::make_shared<Heightfield>(in.domain);
  maps.deposition = std::make_shared<Heightfield>(in.domain);
  maps.flow = std::make_shared<Heightfield>(in.domain);
  double amax = dx * dy;
  for (double a : area) amax = std::max(amax, a);
  const double lmax = std::log(amax / (dx * dy));
  for (std::size_t k = 0; k < n; ++k) {
    maps.out->data[k] = static_cast<float>(z[k]);
    maps.erosion->data[k] = static_cast<float>(ero[k]);
    maps.deposition->data[k] = static_cast<float>(dep[k]);
    maps.flow->data[k] = lmax > 0 && !area.empty() ? static_cast<float>(std::log(area[k] / (dx * dy)) / lmax) : 0.0f;
  }
  if (accumulation) {
    *accumulation = std::make_shared<Heightfield>(in.domain);
    for (std::size_t k = 0; k < n; ++k) (*accumulation)->data[k] = static_cast<float>(area.empty() ? dx * dy : area[k]);
  }
  return maps;
}

}  // namespace orogen::erosion
