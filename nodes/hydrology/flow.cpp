#include "nodes/hydrology/flow.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>

#include "graph/cost_query.h"
#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/huge_page_buffer.h"
#include "nodes/common/match_domain.h"

namespace orogen::hydrology {
namespace {

std::vector<float> routed_height(const Heightfield& in, bool fill, const ExecContext* ctx) {
  std::vector<float> z = in.data;
  if (fill) fill_depressions(FlowGrid::of(in.domain), z, FlatMode::Epsilon, {}, ctx);
  return z;
}

const char* kMethodDoc =
    "d8: all flow to the steepest neighbor (O'Callaghan & Mark 1984); dinf: split between the two neighbors "
    "of the steepest facet (Tarboton 1997); mfd: to every lower neighbor in proportion to tan(beta)^exponent "
    "(Freeman 1991, Holmgren 1994)";

FlowMethod method_of(const ExecContext& ctx) { return static_cast<FlowMethod>(ctx.enum_index("method")); }

}  // namespace

float flow_map_value(double acc, double lo, double hi) {
  if (!(hi > lo)) return acc >= hi ? 1.0f : 0.0f;
  const double t = std::log(std::max(acc, lo) / lo) / std::log(hi / lo);
  return static_cast<float>(std::clamp(t, 0.0, 1.0));
}

float wetness_value(double acc, double width, float slope, double min_slope) {
  return static_cast<float>(std::log(std::max(acc, 1e-12) / width / std::max<double>(slope, min_slope)));
}

AccumulationResult flow_accumulation(const Heightfield& in, const Heightfield* rainfall, const AccumulationParams& p,
                                     const ExecContext* ctx) {
  const FlowGrid g = FlowGrid::of(in.domain);
  // Routed on the input itself when nothing is filled: no copy.
  const std::vector<float> filled = p.fill ? routed_height(in, true, ctx) : std::vector<float>();
  const std::span<const float> z = p.fill ? std::span<const float>(filled) : std::span<const float>(in.data);
  std::vector<float> weight;
  if (rainfall) {
    require_same_grid(rainfall->domain, in.domain, "rainfall");
    weight.resize(g.size());
    for (std::size_t c = 0; c < g.size(); ++c)
      weight[c] = static_cast<float>(std::max(0.0f, rainfall->data[c]) * g.cell_area());
  }
  std::vector<double> acc;
  if (p.method == FlowMethod::D8 && !rainfall) {
    acc = d8_area(g, d8_flow(g, z, {}, ctx), ctx);
  } else {
    acc = accumulate(g, z, RoutingOptions{p.method, p.exponent, {}}, weight, ctx);
  }
  // The flow map and the wetness index (a slope pass and two logarithms per cell) only when asked for.
  const std::vector<float> slope = p.wetness ? steepest_slope(g, z, ctx) : std::vector<float>();
  AccumulationResult r;
  r.accumulation = std::make_shared<Heightfield>();
  r.accumulation->domain = in.domain;
  huge_pages::resize_fresh(r.accumulation->data, g.size());  // fewer first-touch faults than a plain grid
  if (p.flow_map) r.flow = std::make_shared<Heightfield>(in.domain);
  if (p.wetness) r.wetness = std::make_shared<Heightfield>(in.domain);
  const double lo = p.flow_min_area > 0.0 ? p.flow_min_area : g.cell_area();
  const double hi = !p.flow_map             ? 0.0
                    : p.flow_max_area > 0.0 ? p.flow_max_area
                                            : *std::max_element(acc.begin(), acc.end());
  const double width = std::sqrt(g.cell_area());  // contour width of a cell
  for_each_row(ctx, g.ny, [&](int j) {
    const std::size_t row = static_cast<std::size_t>(g.index(0, j));
    for (std::size_t c = row; c < row + static_cast<std::size_t>(g.nx); ++c)
      r.accumulation->data[c] = static_cast<float>(acc[c]);
    if (p.flow_map)
      for (std::size_t c = row; c < row + static_cast<std::size_t>(g.nx); ++c)
        r.flow->data[c] = flow_map_value(acc[c], lo, hi);
    if (p.wetness)
      for (std::size_t c = row; c < row + static_cast<std::size_t>(g.nx); ++c)
        r.wetness->data[c] = wetness_value(acc[c], width, slope[c], p.min_slope);
  });
  return r;
}

DirectionResult flow_direction(const Heightfield& in, FlowMethod method, double exponent, bool fill,
                               const ExecContext* ctx, DirectionMaps maps) {
  const FlowGrid g = FlowGrid::of(in.domain);
  const std::vector<float> z = routed_height(in, fill, ctx);
  DirectionResult r;
  if (maps.angle) r.angle = std::make_shared<Heightfield>(in.domain);
  if (maps.vector) {
    r.dx = std::make_shared<Heightfield>(in.domain);
    r.dy = std::make_shared<Heightfield>(in.domain);
  }
  if (maps.slope) r.slope = std::make_shared<Heightfield>(in.domain);
  direction_maps(g, z, {0, 0}, RoutingOptions{method, exponent, {}}, r, ctx);
  return r;
}

void direction_maps(const FlowGrid& g, std::span<const float> z, glm::ivec2 first, const RoutingOptions& opt,
                    DirectionResult& r, const ExecContext* ctx) {
  const Heightfield* any = r.angle ? r.angle.get() : r.dx ? r.dx.get() : r.slope.get();
  if (!any) return;
  const int w = any->domain.width(), h = any->domain.height();
  const std::vector<float> slope = r.slope ? steepest_slope(g, z, ctx) : std::vector<float>();
  const bool directions = r.angle || r.dx;
  for_each_row(ctx, h, [&](int j) {
    for (int i = 0; i < w; ++i) {
      const std::size_t c = static_cast<std::size_t>(j) * static_cast<std::size_t>(w) + static_cast<std::size_t>(i);
      const int gi = first.x + i, gj = first.y + j;
      if (r.slope) r.slope->data[c] = slope[static_cast<std::size_t>(g.index(gi, gj))];
      if (!directions) continue;
      int nb[8];
      double fr[8];
      const int n = flow_proportions(g, z, gi, gj, opt, nb, fr);
      double vx = 0.0, vy = 0.0;
      for (int m = 0; m < n; ++m) {
        const double ex = kDi[nb[m]] * g.dx, ey = kDj[nb[m]] * g.dy, len = std::hypot(ex, ey);
        vx += fr[m] * ex / len;
        vy += fr[m] * ey / len;
      }
      const double len = std::hypot(vx, vy);
      if (len > 0.0) {
        if (r.dx) {
          r.dx->data[c] = static_cast<float>(vx / len);
          r.dy->data[c] = static_cast<float>(vy / len);
        }
        if (r.angle) {
          double a = std::atan2(vy, vx) * (180.0 / std::numbers::pi);
          if (a < 0.0) a += 360.0;
          r.angle->data[c] = static_cast<float>(a >= 360.0 ? 0.0 : a);
        }
      } else if (r.angle) {
        r.angle->data[c] = -1.0f;
      }
    }
  });
}

WatershedResult watersheds(const Heightfield& in, bool fill, double min_area, const ExecContext* ctx) {
  const FlowGrid g = FlowGrid::of(in.domain);
  const std::vector<float> z = routed_height(in, fill, ctx);
  const D8Flow f = d8_flow(g, z, {}, ctx);
  const auto order = stack_order(g, f);
  int count = 0;
  const auto label = basin_labels(f, order, &count);
  std::vector<std::size_t> cells(static_cast<std::size_t>(count), 0);
  for (std::int32_t l : label) ++cells[static_cast<std::size_t>(l)];
  // Number by decreasing area, ties by outlet order.
  std::vector<std::int32_t> rank(static_cast<std::size_t>(count));
  std::iota(rank.begin(), rank.end(), 0);
  std::stable_sort(rank.begin(), rank.end(), [&](std::int32_t a, std::int32_t b) { return cells[a] > cells[b]; });
  std::vector<std::int32_t> id(static_cast<std::size_t>(count), 0);
  WatershedResult r;
  for (std::int32_t k = 0; k < count; ++k) {
    const std::int32_t b = rank[static_cast<std::size_t>(k)];
    if (static_cast<double>(cells[b]) * g.cell_area() >= min_area && cells[b] > 0) id[b] = ++r.basins;
  }
  r.id = std::make_shared<Heightfield>(in.domain);
  r.area = std::make_shared<Heightfield>(in.domain);
  for (std::size_t c = 0; c < g.size(); ++c) {
    r.id->data[c] = static_cast<float>(id[label[c]]);
    r.area->data[c] = static_cast<float>(static_cast<double>(cells[label[c]]) * g.cell_area());
  }
  return r;
}

OROGEN_NODE(FlowAccumulation) {
  b.distribution(Distribution::TileGraph);
  b.reach_global();  // flow routing over the whole domain
  b.category("hydrology")
      .description(
          "Upslope contributing area of every cell in m^2, optionally weighted by a rainfall field, routed with D8, "
          "D-infinity or multiple flow directions; depressions are filled first (Priority-Flood+epsilon, Barnes et al. "
          "2014) so flow crosses lakes. Also the normalized log flow map used for texturing (0 at flow_min_area, 1 at "
          "flow_max_area) and the topographic wetness index ln(a / tan beta) (Beven & Kirkby 1979) with a the "
          "specific catchment area (area per metre of contour). Accumulation by dependency counting (Barnes 2017, "
          "'Parallel non-divergent flow accumulation for trillion cell digital elevation models'); each cell adds its "
          "donors' shares in a fixed neighbor order, so tiled and distributed builds give the same sums bit for bit.");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.input("rainfall_weight", PortType::Heightfield)
      .unit(Unit::Unitless)
      .optional()
      .description("Relative rainfall per cell (unitless weight, 1 = nominal)");
  b.output("out", PortType::Heightfield)
      .description("Accumulated (rainfall-weighted) upslope area, m^2, the cell included")
      .kind(OutputKind::Scalar);
  b.output("flow", PortType::Heightfield).description("Normalized log flow map in [0, 1]").kind(OutputKind::Mask);
  b.output("wetness", PortType::Heightfield)
      .description("Topographic wetness index ln(a / tan beta), a in metres")
      .kind(OutputKind::Scalar);
  b.param_enum("method", {"d8", "dinf", "mfd"}, "mfd").description(kMethodDoc);
  b.param_float("exponent", 1.1)
      .unit(Unit::Unitless)
      .range(0.1, 100.0)
      .soft_range(1.0, 10.0)
      .description("MFD only: proportions follow tan(beta)^exponent (1.1 Freeman 1991; larger converges to D8)");
  b.param_bool("fill", true).description("Fill depressions (epsilon) before routing, so that flow crosses lakes");
  b.param_float("flow_min_area", 0.0)
      .range(0.0, 1e12)
      .soft_range(0.0, 1e5)
      .unit(Unit::SquareMetre)
      .description("Area mapped to 0 in the flow map (0: one cell)");
  b.param_float("flow_max_area", 0.0)
      .range(0.0, 1e14)
      .soft_range(0.0, 1e8)
      .unit(Unit::SquareMetre)
      .description("Area mapped to 1 in the flow map (0: the largest accumulation)");
  b.param_float("min_gradient", 1e-3)
      .range(1e-9, 1.0)
      .unit(Unit::MetrePerMetre)
      .description("Floor of tan(beta) in the wetness index (flats)");
  // Working memory beyond the outputs, 16 bytes a sample (calibrated on its measured peak:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 16); });
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const auto rain = secondary_input<Heightfield>(ctx, "rainfall_weight", in->domain);
    const AccumulationParams p{method_of(ctx),
                               ctx.param<double>("exponent"),
                               ctx.param<bool>("fill"),
                               ctx.param<double>("flow_min_area"),
                               ctx.param<double>("flow_max_area"),
                               ctx.param<double>("min_gradient"),
                               ctx.output_requested("flow"),
                               ctx.output_requested("wetness")};
    AccumulationResult r = flow_accumulation(*in, rain.get(), p, &ctx);
    ctx.set_output("out", r.accumulation);
    if (r.flow) ctx.set_output("flow", r.flow);
    if (r.wetness) ctx.set_output("wetness", r.wetness);
  });
}

OROGEN_NODE(FlowDirection) {
  b.distribution(Distribution::TileGraph);
  // Filling first makes a cell's direction depend on the whole domain; without it, only on its 8 neighbours (so
  // tiled and distributed builds compute it per tile with a one-sample halo).
  b.reach([](const ParamView& p) { return p.get<bool>("fill") ? Reach::global() : Reach::local(0, 1); },
          "global (fill on); local, 1 sample (fill off)");
  b.category("hydrology")
      .description(
          "Direction water leaves each cell: the proportion-weighted mean of the receiver directions for D8 "
          "(O'Callaghan & Mark 1984), D-infinity (Tarboton 1997) or MFD (Freeman 1991, Holmgren 1994), as an angle "
          "and a unit vector, plus the steepest-descent slope tan(beta) in world units.");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.output("out", PortType::Heightfield)
      .description("Flow angle, degrees counter-clockwise from +x in [0, 360); -1 where nothing drains (border, pits)")
      .kind(OutputKind::Scalar);
  b.output("dx", PortType::Heightfield)
      .description("x component of the unit flow vector (0 where nothing drains)")
      .kind(OutputKind::Signed);
  b.output("dy", PortType::Heightfield)
      .description("y component of the unit flow vector (0 where nothing drains)")
      .kind(OutputKind::Signed);
  b.output("gradient", PortType::Heightfield)
      .unit(Unit::MetrePerMetre)
      .description("tan(beta) of the steepest descent, m/m")
      .kind(OutputKind::Scalar);
  b.param_enum("method", {"d8", "dinf", "mfd"}, "d8").description(kMethodDoc);
  b.param_float("exponent", 1.1)
      .unit(Unit::Unitless)
      .range(0.1, 100.0)
      .soft_range(1.0, 10.0)
      .description("MFD only: proportions follow tan(beta)^exponent");
  b.param_bool("fill", true).description("Fill depressions (epsilon) first, so every cell but the border drains");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const DirectionMaps maps{ctx.output_requested("out"), ctx.output_requested("dx") || ctx.output_requested("dy"),
                             ctx.output_requested("gradient")};
    DirectionResult r =
        flow_direction(*in, method_of(ctx), ctx.param<double>("exponent"), ctx.param<bool>("fill"), &ctx, maps);
    if (r.angle) ctx.set_output("out", r.angle);
    if (r.dx) ctx.set_output("dx", r.dx);
    if (r.dy) ctx.set_output("dy", r.dy);
    if (r.slope) ctx.set_output("gradient", r.slope);
  });
}

OROGEN_NODE(Watersheds) {
  b.distribution(Distribution::TileGraph);
  b.reach_global();  // flow routing over the whole domain
  b.category("hydrology")
      .description(
          "Drainage basins: every cell labeled with the outlet its D8 flow reaches (border cells and, without "
          "filling, pits), by Priority-Flood filling (Barnes, Lehman & Mulla 2014) and the receiver tree (Braun & "
          "Willett 2013). Basins are numbered by decreasing area; those under min_area get 0.");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.output("out", PortType::Heightfield)
      .description("Basin number 1, 2, ... by decreasing area; 0 for basins under min_area")
      .kind(OutputKind::Scalar);
  b.output("area", PortType::Heightfield).description("Area of the cell's basin, m^2").kind(OutputKind::Scalar);
  b.param_bool("fill", true).description("Fill depressions first, so basins end at the border, not at pits");
  b.param_float("min_area", 0.0)
      .range(0.0, 1e14)
      .soft_range(0.0, 1e7)
      .unit(Unit::SquareMetre)
      .description("Smaller basins are labeled 0");
  // Working memory beyond the outputs, 16 bytes a sample (calibrated on its measured peak:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 16); });
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    WatershedResult r = watersheds(*in, ctx.param<bool>("fill"), ctx.param<double>("min_area"), &ctx);
    ctx.set_output("out", r.id);
    ctx.set_output("area", r.area);
  });
}

}  // namespace orogen::hydrology
