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
#include "nodes/hydrology/water_flow_step.h"

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
  WaterFlowGrid grid(g.nx, g.ny, g.cell_area(), in.data.data());
  // Every sum over the domain is exact (order independent), so tiles' partial sums give the same bits.
  ExactDoubleSum rain, border, sink, stored;
  std::vector<std::size_t> drains;
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const std::size_t c = grid.at(i, j);
      grid.w[c] = water_initial_depth(rainfall ? rainfall->data[c] : p.rainfall, p.infiltration);
      rain.add(grid.w[c] * grid.area);
      grid.drain[c] = g.on_border(i, j) ? kBorderDrain : (sinks && sinks->data[c] > 0.5f ? kSinkDrain : kNoDrain);
      if (grid.drain[c]) drains.push_back(c);
    }
  // Water on a drain leaves at once (counted).
  auto empty_drains = [&] {
    for (const std::size_t c : drains) {
      (grid.drain[c] == kBorderDrain ? border : sink).add(grid.w[c] * grid.area);
      grid.w[c] = 0.0;
    }
  };
  empty_drains();
  WaterFlowResult r;
  std::vector<ExactDoubleSum> row_moved(static_cast<std::size_t>(g.ny));
  ExactDoubleSum total_moved;
  for (int it = 0; it < p.max_iterations; ++it) {
    if (ctx) {
      ctx->check_cancelled();
      ctx->progress(static_cast<double>(it) / p.max_iterations);
    }
    for_each_row(nullptr, g.ny, [&](int j) {
      ExactDoubleSum& m = row_moved[static_cast<std::size_t>(j)];
      m = ExactDoubleSum();
      water_spread_row(grid, j, 0, g.nx, 0, g.nx, m);
    });
    ExactDoubleSum moved_sum;
    for (const ExactDoubleSum& m : row_moved) moved_sum.add(m);
    const double moved = moved_sum.value();
    if (!(moved > 0.0)) break;
    for_each_row(nullptr, g.ny, [&](int j) { water_gather_row(grid, j, 0, g.nx); });
    std::swap(grid.w, grid.next);
    empty_drains();
    total_moved.add(moved_sum);
    r.iterations = it + 1;
    if (water_flow_settled(moved, total_moved.value(), p.threshold)) break;
  }
  r.depth = std::make_shared<Heightfield>(in.domain);
  r.flux = std::make_shared<Heightfield>(in.domain);
  for (std::size_t c = 0; c < n; ++c) {
    r.depth->data[c] = static_cast<float>(std::max(0.0, grid.w[c]));
    r.flux->data[c] = static_cast<float>(grid.flux[c]);
    stored.add(grid.w[c] * grid.area);
  }
  r.rain = rain.value(), r.stored = stored.value(), r.border = border.value(), r.sinks = sink.value();
  return r;
}

OROGEN_NODE(WaterFlow) {
  b.distribution(Distribution::HaloExchange);
  b.reach_global();  // a simulation: every output sample depends on the whole input
  b.category("hydrology")
      .description(
          "Where rain water settles: rainfall minus infiltration as the initial water, then repeated 8-neighbor "
          "redistribution on the water surface (after Long 2016, 'Using procedural methods to generate realistic "
          "virtual rural worlds', section 3.3, corrected so that water follows the water surface and never moves "
          "uphill): each wet cell sends min(depth, half its largest surface drop) to its lower neighbors in "
          "proportion to the drops, until an iteration moves less than `threshold` times all water moved so far. "
          "Water is conserved exactly except what drains at the border or into sink cells, which the report counts. "
          "Every sum over the domain (the stop test, the report) is exact, independent of the order of addition, so "
          "the result is bit-identical for any thread count, and in a tiled or distributed build, where tiles "
          "exchange halos of water every few iterations, for any tiling and rank count.");
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
