#include "nodes/hydrology/water_flow.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "graph/cost_query.h"
#include "graph/registry.h"
#include "graph/report.h"
#include "nodes/common/finite_inputs.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/match_domain.h"
#include "nodes/common/report_builder.h"
#include "nodes/common/work_bounds.h"
#include "nodes/hydrology/flow_routing.h"

namespace orogen::hydrology {

std::string WaterFlowResult::json() const {
  ReportJson j;
  j["rain_m3"] = rain;
  j["stored_m3"] = stored;
  j["border_outflow_m3"] = border;
  j["sink_inflow_m3"] = sinks;
  j["balance_error_m3"] = rain - stored - border - sinks;
  j["iterations"] = iterations;
  return report_text(j);
}

WaterFlowResult water_flow(const Heightfield& in, const Heightfield* rainfall, const Heightfield* sinks,
                           const WaterFlowParams& p, const ExecContext* ctx) {
  const FlowGrid g = FlowGrid::of(in.domain);
  if (rainfall) require_same_grid(rainfall->domain, in.domain, "rainfall");
  if (sinks) require_same_grid(sinks->domain, in.domain, "sinks");
  require_finite_inputs("WaterFlow", {{"in", &in}, {"rainfall", rainfall}, {"sinks", sinks}});
  const std::size_t n = g.size();
  check_work(static_cast<double>(p.max_iterations) * static_cast<double>(n), "WaterFlow (max_iterations x samples)",
             "lower max_iterations or use a coarser grid");
  const double area = g.cell_area();
  std::vector<double> w(n), next(n), out(n, 0.0), scale(n, 0.0), flux(n, 0.0);
  std::vector<std::uint8_t> drain(n, 0);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const std::size_t c = static_cast<std::size_t>(g.index(i, j));
      const double mm = rainfall ? rainfall->data[c] : p.rainfall;
      w[c] = std::max(0.0, mm - p.infiltration) / 1000.0;
      drain[c] = g.on_border(i, j) ? 1 : (sinks && sinks->data[c] > 0.5f ? 2 : 0);
    }
  WaterFlowResult r;
  for (double v : w) r.rain += v * area;
  // Water on a drain leaves at once (counted).
  auto empty_drains = [&](std::vector<double>& water) {
    for (std::size_t c = 0; c < n; ++c)
      if (drain[c]) {
        (drain[c] == 1 ? r.border : r.sinks) += water[c] * area;
        water[c] = 0.0;
      }
  };
  empty_drains(w);
  const float* z = in.data.data();
  std::vector<double> row_moved(static_cast<std::size_t>(g.ny));
  double total_moved = 0.0;
  for (int it = 0; it < p.max_iterations; ++it) {
    if (ctx) {
      ctx->check_cancelled();
      ctx->progress(static_cast<double>(it) / p.max_iterations);
    }
    // Each wet cell sends min(w, largest surface drop / 2) to its lower neighbours (on the water surface),
    // in proportion to the drops.
    for_each_row(nullptr, g.ny, [&](int j) {
      double moved = 0.0;
      for (int i = 0; i < g.nx; ++i) {
        const std::int32_t c = g.index(i, j);
        out[c] = scale[c] = 0.0;
        if (!(w[c] > 0.0)) continue;
        const double s = z[c] + w[c];
        double dmax = 0.0, dsum = 0.0;
        for (int k = 0; k < 8; ++k) {
          if (!g.inside(i + kDi[k], j + kDj[k])) continue;
          const std::int32_t m = c + g.offset(k);
          const double d = s - (z[m] + w[m]);
          if (d > 0.0) {
            dmax = std::max(dmax, d);
            dsum += d;
          }
        }
        if (dsum > 0.0) {
          out[c] = std::min(w[c], 0.5 * dmax);
          scale[c] = out[c] / dsum;
          moved += out[c];
        }
      }
      row_moved[static_cast<std::size_t>(j)] = moved;
    });
    double moved = 0.0;
    for (double m : row_moved) moved += m;
    if (!(moved > 0.0)) break;
    // Gather what the neighbours send (same drops as they computed), so each row is independent.
    for_each_row(nullptr, g.ny, [&](int j) {
      for (int i = 0; i < g.nx; ++i) {
        const std::int32_t c = g.index(i, j);
        const double s = z[c] + w[c];
        double gain = 0.0;
        for (int k = 0; k < 8; ++k) {
          if (!g.inside(i + kDi[k], j + kDj[k])) continue;
          const std::int32_t m = c + g.offset(k);
          if (scale[m] == 0.0) continue;
          const double d = (z[m] + w[m]) - s;
          if (d > 0.0) gain += scale[m] * d;
        }
        next[c] = w[c] - out[c] + gain;
        flux[c] += out[c] * area;
      }
    });
    std::swap(w, next);
    empty_drains(w);
    total_moved += moved;
    r.iterations = it + 1;
    if (moved < p.threshold * total_moved) break;
  }
  r.depth = std::make_shared<Heightfield>(in.domain);
  r.flux = std::make_shared<Heightfield>(in.domain);
  for (std::size_t c = 0; c < n; ++c) {
    r.depth->data[c] = static_cast<float>(std::max(0.0, w[c]));
    r.flux->data[c] = static_cast<float>(flux[c]);
    r.stored += w[c] * area;
  }
  return r;
}

OROGEN_NODE(WaterFlow) {
  b.distribution(Distribution::Gathered);
  b.reach_global();  // flow routing over the whole domain
  b.category("hydrology")
      .description(
          "Where rain water settles: rainfall minus infiltration as the initial water, then repeated 8-neighbor "
          "redistribution on the water surface (after Long 2016, 'Using procedural methods to generate realistic "
          "virtual rural worlds', section 3.3, corrected so that water follows the water surface and never moves "
          "uphill): each wet cell sends min(depth, half its largest surface drop) to its lower neighbors in "
          "proportion to the drops, until an iteration moves less than `threshold` times all water moved so far. "
          "Water is conserved exactly except what drains at the border or into sink cells, which the report counts.");
  b.input("in", PortType::Heightfield).description("Terrain height, metres");
  b.input("rainfall", PortType::Heightfield)
      .unit(Unit::Millimetre)
      .optional()
      .description("Rainfall per cell, mm (replaces the rainfall parameter)");
  b.input("sinks", PortType::Heightfield).optional().description("Cells above 0.5 drain (sea, swallow holes)");
  b.output("out", PortType::Heightfield).description("Water depth, metres").kind(OutputKind::WaterDepth);
  b.output("flux", PortType::Heightfield)
      .description("Water volume that flowed out of each cell over the run, m^3")
      .kind(OutputKind::Scalar);
  b.output("report", PortType::Report)
      .description("Water balance: rain, stored, border outflow, sink inflow (m^3), iterations");
  b.param_float("rainfall", 50.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 500.0)
      .unit(Unit::Millimetre)
      .description("Uniform rainfall when no field is connected");
  b.param_float("infiltration", 10.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 200.0)
      .unit(Unit::Millimetre)
      .description("Soaked into the soil before any flow");
  b.param_float("threshold", 1e-3)
      .unit(Unit::Unitless)
      .range(0.0, 1.0)
      .description("Stop when an iteration moves less than this fraction of all water moved so far");
  b.param_int("max_iterations", 1000)
      .unit(Unit::Count)
      .range(1, 1000000)
      .soft_range(1, 10000)
      .description("Upper bound on the iterations");
  // Working memory beyond the outputs, 32 bytes a sample (calibrated on its measured peak:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 32); });
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const auto rain = secondary_input<Heightfield>(ctx, "rainfall", in->domain);
    const auto sinks = secondary_input<Heightfield>(ctx, "sinks", in->domain);
    const WaterFlowParams p{ctx.param<double>("rainfall"), ctx.param<double>("infiltration"),
                            ctx.param<double>("threshold"),
                            static_cast<int>(ctx.param<std::int64_t>("max_iterations"))};
    WaterFlowResult r = water_flow(*in, rain.get(), sinks.get(), p, &ctx);
    ctx.set_output("out", r.depth);
    ctx.set_output("flux", r.flux);
    ctx.set_output("report", make_report(r.json()));
  });
}

}  // namespace orogen::hydrology
