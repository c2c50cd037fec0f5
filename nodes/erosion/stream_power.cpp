#include "nodes/erosion/stream_power.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <queue>
#include <vector>

#include "nodes/common/cancellable_rows.h"
#include "nodes/common/finite_inputs.h"
#include "nodes/erosion/stream_power_kernel.h"
#include "nodes/hydrology/basin_graph.h"
#include "nodes/hydrology/flow_routing.h"

namespace orogen::erosion {
namespace {

// The smallest increment that still orders the filled surface: relative to the height so that it survives
// double rounding, and far below any real relief.
inline double raise(double z) { return z + std::max(1e-9, std::abs(z) * 1e-12); }

// The state of one run and its stages, in the order a step runs them: uplift, hillslope diffusion, routing
// with the implicit incision (over the basin graph or a Priority-Flood fill), the change of the step; then the
// final fill in float and the output maps.
class StreamPowerRun {
 public:
  StreamPowerRun(const Heightfield& in, const StreamPowerParams& p, const Heightfield* uplift, const Heightfield* mask,
                 const std::vector<unsigned char>* outlets)
      : in_(in),
        p_(p),
        w_(in.width()),
        h_(in.height()),
        n_(in.data.size()),
        dx_(in.domain.spacing.x),
        dy_(in.domain.spacing.y),
        grid_(hydrology::FlowGrid::of(in.domain)),
        basin_graph_(p.depressions == StreamPowerParams::Depressions::BasinGraph),
        schedule_(StreamPowerSchedule::of(p, dx_, dy_, n_)),
        incision_(p, grid_, schedule_.dt) {
    // Fixed base level: the given outlets, else the border. Cells under sea level join them step by step
    // (uplift can lift the sea floor into land).
    fixed_.assign(n_, 0);
    outlet_.assign(n_, 0);
    if (outlets) {
      fixed_ = *outlets;
    } else {
      for (int j = 0; j < h_; ++j)
        for (int i = 0; i < w_; ++i) fixed_[in.index(i, j)] = i == 0 || j == 0 || i == w_ - 1 || j == h_ - 1;
    }
    z_.assign(in.data.begin(), in.data.end());
    ero_.assign(n_, 0.0);
    dep_.assign(n_, 0.0);
    zprev_.resize(n_);
    ztmp_.resize(n_);
    kfac_.resize(n_);
    ufac_.resize(n_);
    for (std::size_t k = 0; k < n_; ++k) {
      kfac_[k] = mask_at(mask, k);
      ufac_[k] = fixed_[k] ? 0.0 : p.uplift * (uplift ? std::max(0.0f, uplift->data[k]) : 1.0f);
    }
    steps_ = schedule_.steps;
    dt_ = schedule_.dt;
    diff_steps_ = schedule_.diff_steps;
    row_max_.resize(static_cast<std::size_t>(h_));
    row_sum_.resize(static_cast<std::size_t>(h_));
    row_count_.resize(static_cast<std::size_t>(h_));
    outs_.border = false;
    outs_.mask = outlet_;
  }

  int steps() const { return steps_; }

  // Uplift of the step, and the base level after it (fixed cells and cells under sea level).
  void uplift(const ExecContext* ctx) {
    for_each_row_unreported(ctx, h_, [&](int j) {
      for (std::size_t k = static_cast<std::size_t>(j) * w_, e = k + w_; k < e; ++k) {
        zprev_[k] = z_[k];
        z_[k] += ufac_[k] * dt_;
        outlet_[k] = fixed_[k] || z_[k] < p_.sea_level;
      }
    });
  }

  // Hillslope diffusion, base level fixed, before the incision: the implicit sweep then cuts through whatever
  // diffusion laid into the channels within the same step, so river profiles stay clean.
  void diffuse(const ExecContext* ctx) {
    for (int sd = 0; sd < diff_steps_; ++sd) {
      const double c = p_.diffusion * dt_ / diff_steps_;
      const double cx = 1.0 / (dx_ * dx_), cy = 1.0 / (dy_ * dy_);
      const int w = w_, h = h_;
      std::vector<double>& z = z_;
      std::vector<double>& ztmp = ztmp_;
      std::vector<double>& ero = ero_;
      std::vector<double>& dep = dep_;
      const std::vector<double>& kfac = kfac_;
      const std::vector<unsigned char>& outlet = outlet_;
      for_each_row_unreported(ctx, h, [&](int j) {
        auto cell = [&](int i, std::size_t k, double zw, double ze, double zs, double zn) {
          const double zc = z[k];
          const double dz = diffusion_change(outlet[k], c, kfac[k], cx, cy, zc, zw, ze, zs, zn);
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
      std::swap(z_, ztmp_);
    }
  }

  // Routing and the implicit incision from the outlets upstream (receivers are already at t + dt).
  void route_and_incise(const ExecContext* ctx) {
    area_.resize(n_);
    if (basin_graph_) {
      // Local D8 over the surface as it is; only the pits' basins are rerouted over their passes (basin
      // graph), then the lakes fill with sediment to just above the pass, one outlet tree per task.
      hydrology::route_basin_graph_fill(grid_, z_, outs_, routing_, dep_, ctx);
      hydrology::accumulate_stack(grid_, routing_, area_);
      const std::int32_t* rcv = routing_.flow.receiver.data();
      const std::uint8_t* dir = routing_.flow.direction.data();
      hydrology::for_each_tree(routing_, [&](std::int32_t first, std::int32_t last) {
        for (std::int32_t q = first; q < last; ++q) {
          const std::int32_t k = routing_.stack[static_cast<std::size_t>(q)];
          incise(k, rcv[k], dir[k]);
        }
      });
    } else {
      // Routing over the depression-filled surface with the hydrology core: closed depressions fill with
      // sediment (Priority-Flood+epsilon), then D8 receivers, the Braun-Willett stack and the drainage area.
      zf_.resize(n_);
      for (std::size_t k = 0; k < n_; ++k) zf_[k] = static_cast<float>(z_[k]);
      zround_ = zf_;
      hydrology::fill_depressions(grid_, zf_, hydrology::FlatMode::Epsilon, outs_, ctx);
      for (std::size_t k = 0; k < n_; ++k)
        if (zf_[k] != zround_[k]) {
          dep_[k] += static_cast<double>(zf_[k]) - z_[k];
          z_[k] = zf_[k];
        }
      flow_ = hydrology::d8_flow(grid_, zf_, outs_, ctx);
      order_ = hydrology::stack_order(grid_, flow_);
      // Whole cells times the cell area, as the run across tiles counts them (exact for any order).
      area_ = hydrology::d8_area(grid_, flow_, ctx);
      for (const std::int32_t k : order_) incise(k, flow_.receiver[k], flow_.direction[k]);
    }
  }

  // The step's largest and mean |dz/dt| over the cells that are not base level.
  void measure_change(StreamPowerStats& st, const ExecContext* ctx) {
    for_each_row_unreported(ctx, h_, [&](int j) {
      double mx = 0, sum = 0;
      std::size_t count = 0;
      for (std::size_t k = static_cast<std::size_t>(j) * w_, e = k + w_; k < e; ++k)
        if (!outlet_[k]) {
          const double c = std::abs(z_[k] - zprev_[k]) / dt_;
          mx = std::max(mx, c);
          sum += c;
          ++count;
        }
      row_max_[static_cast<std::size_t>(j)] = mx;
      row_sum_[static_cast<std::size_t>(j)] = sum;
      row_count_[static_cast<std::size_t>(j)] = count;
    });
    double mx = 0, sum = 0;
    std::size_t count = 0;
    for (int j = 0; j < h_; ++j) {
      mx = std::max(mx, row_max_[static_cast<std::size_t>(j)]);
      sum += row_sum_[static_cast<std::size_t>(j)];
      count += row_count_[static_cast<std::size_t>(j)];
    }
    st.max_change_last_step = mx;
    st.mean_change_last_step = count ? sum / count : 0.0;
  }

  // The last diffusion sub-steps may leave shallow closed depressions on filled flats, and the result is
  // rounded to float: fill them in float like every step does, so the result drains (sediment settles in
  // them; recorded as deposition).
  void settle_in_float(const ExecContext* ctx) {
    zf_.resize(n_);
    for (std::size_t k = 0; k < n_; ++k) {
      outlet_[k] = fixed_[k] || z_[k] < p_.sea_level;
      zf_[k] = static_cast<float>(z_[k]);
    }
    zround_ = zf_;
    if (basin_graph_) {
      // Route the float surface over its passes and fill its lakes one float step above the pass.
      hydrology::route_basin_graph_fill(grid_, std::span<float>(zf_), outs_, routing_, {}, ctx);
    } else {
      hydrology::fill_depressions(grid_, zf_, hydrology::FlatMode::Epsilon, outs_, ctx);
    }
    for (std::size_t k = 0; k < n_; ++k) {
      if (zf_[k] != zround_[k]) dep_[k] += static_cast<double>(zf_[k]) - z_[k];
      z_[k] = zf_[k];
    }
  }

  ErosionMaps maps(std::shared_ptr<Heightfield>* accumulation) const {
    ErosionMaps maps;
    maps.out = std::make_shared<Heightfield>(in_.domain);
    maps.erosion = std::make_shared<Heightfield>(in_.domain);
    maps.deposition = std::make_shared<Heightfield>(in_.domain);
    maps.flow = std::make_shared<Heightfield>(in_.domain);
    double amax = dx_ * dy_;
    for (double a : area_) amax = std::max(amax, a);
    const double lmax = std::log(amax / (dx_ * dy_));
    for (std::size_t k = 0; k < n_; ++k) {
      maps.out->data[k] = static_cast<float>(z_[k]);
      maps.erosion->data[k] = static_cast<float>(ero_[k]);
      maps.deposition->data[k] = static_cast<float>(dep_[k]);
      maps.flow->data[k] =
          lmax > 0 && !area_.empty() ? static_cast<float>(std::log(area_[k] / (dx_ * dy_)) / lmax) : 0.0f;
    }
    if (accumulation) {
      *accumulation = std::make_shared<Heightfield>(in_.domain);
      for (std::size_t k = 0; k < n_; ++k)
        (*accumulation)->data[k] = static_cast<float>(area_.empty() ? dx_ * dy_ : area_[k]);
    }
    return maps;
  }

 private:
  // Implicit incision of cell k towards its receiver rc (already at t + dt) along D8 direction `direction`.
  void incise(std::int32_t k, std::int32_t rc, int direction) {
    if (rc == k || !incision_.incises(area_[k])) return;
    const double z0 = z_[k], zn = incision_.incised(z0, z_[rc], area_[k], kfac_[k], direction);
    ero_[k] += z0 - zn;
    z_[k] = zn;
  }

  const Heightfield& in_;
  const StreamPowerParams& p_;
  const int w_, h_;
  const std::size_t n_;
  const double dx_, dy_;
  const hydrology::FlowGrid grid_;
  const bool basin_graph_;
  const StreamPowerSchedule schedule_;
  const StreamPowerIncision incision_;
  int steps_ = 1, diff_steps_ = 0;
  double dt_ = 0.0;
  std::vector<unsigned char> fixed_, outlet_;
  std::vector<double> z_, ero_, dep_, zprev_, ztmp_, kfac_, ufac_, area_;
  std::vector<float> zf_, zround_;
  hydrology::D8Flow flow_;
  hydrology::BasinRouting routing_;
  hydrology::Outlets outs_;
  std::vector<std::int32_t> order_;
  std::vector<double> row_max_, row_sum_;
  std::vector<std::size_t> row_count_;
};

}  // namespace

ErosionMaps stream_power(const Heightfield& in, const StreamPowerParams& p, const Heightfield* uplift,
                         const Heightfield* mask, const ExecContext* ctx, StreamPowerStats* stats,
                         const std::vector<unsigned char>* outlets, std::shared_ptr<Heightfield>* accumulation) {
  require_finite_inputs("StreamPower", {{"in", &in}, {"uplift", uplift}, {"mask", mask}});
  StreamPowerRun run(in, p, uplift, mask, outlets);
  StreamPowerStats st;
  for (int s = 0; s < run.steps(); ++s) {
    check_cancelled(ctx);
    run.uplift(ctx);
    run.diffuse(ctx);
    run.route_and_incise(ctx);
    run.measure_change(st, ctx);
    report(ctx, static_cast<double>(s + 1) / run.steps());
  }
  st.steps = run.steps();
  if (stats) *stats = st;
  run.settle_in_float(ctx);
  return run.maps(accumulation);
}

}  // namespace orogen::erosion
