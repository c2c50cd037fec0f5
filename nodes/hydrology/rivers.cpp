#include "nodes/hydrology/rivers.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "graph/cost_query.h"
#include "graph/registry.h"
#include "nodes/common/match_domain.h"
#include "nodes/hydrology/channels.h"
#include "nodes/hydrology/flow_routing.h"

namespace orogen::hydrology {
namespace {

// A polyline in double precision with its per-vertex values, for smoothing before rounding to float.
struct Line {
  std::vector<glm::dvec3> p;
  std::vector<double> area, width, order;
};

Line chaikin(const Line& in) {
  if (in.p.size() < 3) return in;
  Line out;
  auto put = [&](std::size_t a, std::size_t b, double t) {
    out.p.push_back(in.p[a] * (1 - t) + in.p[b] * t);
    out.area.push_back(in.area[a] * (1 - t) + in.area[b] * t);
    out.width.push_back(in.width[a] * (1 - t) + in.width[b] * t);
    out.order.push_back(t < 0.5 ? in.order[a] : in.order[b]);
  };
  put(0, 0, 0.0);
  for (std::size_t k = 0; k + 1 < in.p.size(); ++k) {
    if (k > 0) put(k, k + 1, 0.25);
    if (k + 2 < in.p.size()) put(k, k + 1, 0.75);
  }
  put(in.p.size() - 1, in.p.size() - 1, 0.0);
  return out;
}

}  // namespace

void draw_curves(const Curves& curves, Heightfield& mask, const Domain* whole) {
  const Domain& d = mask.domain;
  const double pixel = std::sqrt(std::abs(d.spacing.x * d.spacing.y));
  const double span = glm::length((whole ? *whole : d).size()) + pixel;
  for (const Curve& c : curves.curves) {
    for (std::size_t k = 0; k + 1 < c.points.size(); ++k) {
      const glm::dvec2 a(c.points[k].x, c.points[k].y), b(c.points[k + 1].x, c.points[k + 1].y);
      // A half-width beyond the grid's diagonal covers the grid as it is (and an infinite one, from a width
      // law's overflow, does not turn the bounds below into -inf); a non-finite end or a NaN width covers
      // nothing.
      const double ra = std::min(0.5 * c.width[k], span), rb = std::min(0.5 * c.width[k + 1], span);
      if (!std::isfinite(a.x + a.y + b.x + b.y) || std::isnan(ra + rb)) continue;
      const double reach = std::max(ra, rb) + pixel;
      const glm::dvec2 lo = d.to_sample(glm::min(a, b) - reach), hi = d.to_sample(glm::max(a, b) + reach);
      // Clamped to the grid before the cast: a curve point far outside (or non-finite) does not fit an int.
      const double last_i = d.width() - 1, last_j = d.height() - 1;
      const int i0 = static_cast<int>(std::clamp(std::floor(std::min(lo.x, hi.x)), 0.0, last_i + 1));
      const int i1 = static_cast<int>(std::clamp(std::ceil(std::max(lo.x, hi.x)), -1.0, last_i));
      const int j0 = static_cast<int>(std::clamp(std::floor(std::min(lo.y, hi.y)), 0.0, last_j + 1));
      const int j1 = static_cast<int>(std::clamp(std::ceil(std::max(lo.y, hi.y)), -1.0, last_j));
      if (!(i0 <= i1 && j0 <= j1)) continue;
      const glm::dvec2 ab = b - a;
      const double len2 = glm::dot(ab, ab);
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
          const glm::dvec2 q = d.position(i, j);
          const double t = len2 > 0.0 ? std::clamp(glm::dot(q - a, ab) / len2, 0.0, 1.0) : 0.0;
          const double dist = glm::length(q - (a + t * ab));
          const double r = ra + (rb - ra) * t;
          const float cover = static_cast<float>(std::clamp(0.5 + (r - dist) / pixel, 0.0, 1.0));
          float& m = mask.at(i, j);
          m = std::max(m, cover);
        }
    }
  }
}

std::shared_ptr<Curves> reach_curves(const std::vector<Reach>& reaches,
                                     const std::function<RiverCell(std::int32_t)>& cell, const RiverParams& p) {
  const double runoff = p.runoff / 1000.0 / 3600.0;  // m/s
  auto width_of = [&](double area) { return p.width_coefficient * std::pow(area * runoff, p.width_exponent); };
  auto lake = [&](std::int32_t c) { return p.split_at_lakes && cell(c).lake; };
  // Pieces of every reach outside lakes (a piece may start and end on one lake cell, the mouth or the
  // outflow). Reaches come downstream first, so the parent's first piece is known when a reach is cut.
  std::vector<std::vector<std::int32_t>> pieces;
  std::vector<int> piece_parent, piece_order;
  std::vector<int> first_piece(reaches.size(), -1);  // most upstream piece of a reach, or the next one downstream
  for (std::size_t ri = 0; ri < reaches.size(); ++ri) {
    const Reach& reach = reaches[ri];
    const int downstream = reach.parent >= 0 ? first_piece[static_cast<std::size_t>(reach.parent)] : -1;
    std::vector<std::vector<std::int32_t>> cut;
    std::vector<std::int32_t> cur;
    const auto& cells = reach.cells;
    auto flush = [&] {
      if (cur.size() >= 2) cut.push_back(cur);
      cur.clear();
    };
    for (std::size_t k = 0; k < cells.size();) {
      if (!lake(cells[k])) {
        cur.push_back(cells[k++]);
        continue;
      }
      std::size_t e = k;  // the wet run is k..e
      while (e + 1 < cells.size() && lake(cells[e + 1])) ++e;
      if (!cur.empty()) cur.push_back(cells[k]);  // the mouth
      flush();
      if (e + 1 < cells.size()) cur.push_back(cells[e]);  // the outflow starts at the lake's last cell
      k = e + 1;
    }
    flush();
    // Emit downstream first so parents have lower indices: the last piece flows into `downstream`.
    int next = downstream;
    for (auto it = cut.rbegin(); it != cut.rend(); ++it) {
      pieces.push_back(std::move(*it));
      piece_parent.push_back(next);
      piece_order.push_back(reach.order);
      next = static_cast<int>(pieces.size()) - 1;
    }
    first_piece[ri] = next;
  }
  auto curves = std::make_shared<Curves>();
  curves->curves.reserve(pieces.size());
  for (std::size_t pi = 0; pi < pieces.size(); ++pi) {
    Line line;
    for (const std::int32_t c : pieces[pi]) {
      const RiverCell rc = cell(c);
      line.p.emplace_back(rc.x, rc.y, static_cast<double>(rc.z));
      line.area.push_back(rc.area);
      line.width.push_back(width_of(rc.area));
      line.order.push_back(piece_order[pi]);
    }
    for (int s = 0; s < p.smoothing; ++s) line = chaikin(line);
    Curve curve;
    curve.parent = piece_parent[pi];
    auto& discharge = curve.attributes["discharge"];
    auto& area = curve.attributes["area"];
    auto& so = curve.attributes["order"];
    for (std::size_t k = 0; k < line.p.size(); ++k) {
      curve.points.emplace_back(static_cast<float>(line.p[k].x), static_cast<float>(line.p[k].y),
                                static_cast<float>(line.p[k].z));
      curve.width.push_back(static_cast<float>(line.width[k]));
      discharge.push_back(static_cast<float>(line.area[k] * runoff));
      area.push_back(static_cast<float>(line.area[k]));
      so.push_back(static_cast<float>(line.order[k]));
    }
    curves->curves.push_back(std::move(curve));
  }
  return curves;
}

RiverResult extract_rivers(const Heightfield& in, const Heightfield* rainfall, const RiverParams& p,
                           const ExecContext* ctx) {
  const FlowGrid g = FlowGrid::of(in.domain);
  std::vector<float> z = in.data, spill(g.size());
  fill_depressions(g, z, FlatMode::Epsilon, {}, ctx, spill);
  const D8Flow f = d8_flow(g, z, {}, ctx);
  std::vector<double> acc;
  if (rainfall) {
    require_same_grid(rainfall->domain, in.domain, "rainfall");
    std::vector<float> weight(g.size());
    for (std::size_t c = 0; c < g.size(); ++c)
      weight[c] = static_cast<float>(std::max(0.0f, rainfall->data[c]) * g.cell_area());
    acc = accumulate_d8(g, f, weight, ctx);
  } else {
    // Whole cells times the cell area, as FlowAccumulation's D8 area: exact in any order, so across tiles too.
    acc = d8_area(g, f, ctx);
  }
  const auto order = stack_order(g, f);
  std::vector<std::uint8_t> channel(g.size());
  for (std::size_t c = 0; c < g.size(); ++c) channel[c] = acc[c] >= p.threshold;
  const auto strahler = strahler_orders(g, f, order, channel);
  const auto reaches = extract_reaches(g, f, order, channel, strahler);
  if (ctx) ctx->check_cancelled();
  RiverResult r;
  // Lake cells: below the flat spill level of their depression.
  r.curves = reach_curves(
      reaches,
      [&](std::int32_t c) {
        const auto u = static_cast<std::size_t>(c);
        return RiverCell{in.domain.x(g.column(c)), in.domain.y(g.row(c)), z[u], acc[u], spill[u] > in.data[u]};
      },
      p);
  r.mask = std::make_shared<Heightfield>(in.domain);
  draw_curves(*r.curves, *r.mask);
  return r;
}

OROGEN_NODE(RiverExtract) {
  b.distribution(Distribution::TileGraph);
  b.reach_global();  // flow routing over the whole domain
  b.category("hydrology")
      .description(
          "Rivers: cells whose contributing area (D8 on the Priority-Flood+epsilon filled terrain, Barnes et al. 2014) "
          "exceeds a threshold, vectorized into one polyline per reach (source or confluence to the next confluence or "
          "outlet; parent = the reach it flows into) with per-vertex height (z, from the filled terrain, so it never "
          "rises downstream), discharge Q = area x runoff, Strahler order (Strahler 1957) and width from the "
          "hydraulic-geometry law w = k Q^b (Leopold & Maddock 1953, b about 0.5); plus a raster river mask drawn with "
          "that width in world units. Optional Chaikin smoothing (Chaikin 1974) keeps the ends; lakes are left without "
          "lines.");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.input("rainfall_weight", PortType::Heightfield)
      .unit(Unit::Unitless)
      .optional()
      .description("Relative rainfall per cell (unitless weight, 1 = nominal)");
  b.output("out", PortType::Curves).description("River reaches; attributes discharge (m^3/s), area (m^2), order");
  b.output("river_mask", PortType::Heightfield)
      .unit(Unit::Unitless)
      .description("River coverage in [0, 1], drawn with the river width")
      .kind(OutputKind::Mask);
  b.param_float("threshold", 1e5)
      .range(1.0, 1e14)
      .soft_range(1e3, 1e8)
      .unit(Unit::SquareMetre)
      .description("Contributing area at which a channel starts");
  b.param_float("runoff", 10.0)
      .range(0.0, 1000.0)
      .soft_range(0.0, 100.0)
      .unit(Unit::MillimetrePerHour)
      .description("Effective runoff rate turning area into discharge");
  b.param_float("width_coefficient", 4.0)
      .range(0.0, 1000.0)
      .soft_range(0.0, 20.0)
      .unit(Unit::WidthCoefficient)
      .description("k of w = k Q^b");
  b.param_float("width_exponent", 0.5)
      .unit(Unit::Unitless)
      .range(0.0, 1.0)
      .description("b of w = k Q^b (about 0.5 in nature)");
  b.param_int("smoothing", 2)
      .unit(Unit::Count)
      .range(0, 5)
      .description("Chaikin corner-cutting passes on each reach (0: cell centers)");
  b.param_bool("split_at_lakes", true)
      .description(
          "Leave lakes (filled depressions) without polylines: a river ends at the shore and its parent is the reach "
          "leaving the lake; off, reaches cross lakes along the filled surface's flow paths");
  // Working memory beyond the outputs, 44 bytes a sample (calibrated on its measured peak:
  // tests/test_peak_memory.cpp).
  b.extra_bytes([](const CostQuery& q) { return per_sample_bytes(q, 44); });
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const auto rain = secondary_input<Heightfield>(ctx, "rainfall_weight", in->domain);
    const RiverParams p{ctx.param<double>("threshold"),
                        ctx.param<double>("runoff"),
                        ctx.param<double>("width_coefficient"),
                        ctx.param<double>("width_exponent"),
                        static_cast<int>(ctx.param<std::int64_t>("smoothing")),
                        ctx.param<bool>("split_at_lakes")};
    RiverResult r = extract_rivers(*in, rain.get(), p, &ctx);
    ctx.set_output("out", r.curves);
    ctx.set_output("river_mask", r.mask);
  });
}

}  // namespace orogen::hydrology
