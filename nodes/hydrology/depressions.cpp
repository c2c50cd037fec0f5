#include "nodes/hydrology/depressions.h"

#include <algorithm>
#include <cmath>

#include "graph/cost_query.h"
#include "graph/registry.h"
#include "nodes/common/huge_page_buffer.h"
#include "nodes/hydrology/flow_routing.h"

namespace orogen::hydrology {

int label_components(int nx, int ny, const std::vector<std::uint8_t>& mask, std::vector<std::int32_t>& label) {
  label.assign(mask.size(), 0);
  std::vector<std::int32_t> queue;
  int count = 0;
  for (std::int32_t c0 = 0; c0 < static_cast<std::int32_t>(mask.size()); ++c0) {
    if (!mask[c0] || label[c0]) continue;
    label[c0] = ++count;
    queue.assign(1, c0);
    for (std::size_t h = 0; h < queue.size(); ++h) {
      const std::int32_t c = queue[h];
      const int i = c % nx, j = c / nx;
      for (int k = 0; k < 8; ++k) {
        const int ii = i + kDi[k], jj = j + kDj[k];
        if (ii < 0 || jj < 0 || ii >= nx || jj >= ny) continue;
        const std::int32_t n = jj * nx + ii;
        if (mask[n] && !label[n]) {
          label[n] = count;
          queue.push_back(n);
        }
      }
    }
  }
  return count;
}

namespace {

std::vector<float> flat_filled(const Heightfield& in, const ExecContext* ctx) {
  std::vector<float> flat = in.data;
  fill_depressions(FlowGrid::of(in.domain), flat, FlatMode::Flat, {}, ctx);
  return flat;
}

}  // namespace

FillResult fill_depressions(const Heightfield& in, const FillParams& p, const ExecContext* ctx) {
  const FlowGrid g = FlowGrid::of(in.domain);
  // Without the lake maps, and unless carving keeps some depressions as lakes, no water level nor lake label
  // is needed: the result is the routing core's call on a copy (the same heights as below, which carves with
  // no lake kept when max_depth is 0, since every wet cell is strictly deeper than 0).
  if (!p.lake_maps && (!p.carve || !(p.max_depth > 0.0))) {
    FillResult r;
    r.out = std::make_shared<Heightfield>();
    r.out->domain = in.domain;
    huge_pages::assign_fresh(r.out->data, in.data);  // fewer first-touch faults than a plain copy
    const FlatMode mode = p.epsilon ? FlatMode::Epsilon : FlatMode::Flat;
    if (!p.carve) {
      fill_depressions(g, r.out->data, mode, {}, ctx);
    } else {
      breach_depressions(g, r.out->data, mode, {}, ctx);  // epsilon: already its own epsilon fill
    }
    return r;
  }
  // Fill with epsilon gives the flat water levels in the same pass.
  std::vector<float> eps, flat;
  if (!p.carve && p.epsilon) {
    eps = in.data;
    flat.resize(eps.size());
    fill_depressions(g, eps, FlatMode::Epsilon, {}, ctx, flat);
  } else {
    flat = flat_filled(in, ctx);
  }
  std::vector<std::uint8_t> wet(flat.size());
  for (std::size_t c = 0; c < flat.size(); ++c) wet[c] = flat[c] > in.data[c];
  std::vector<std::int32_t> label;
  int count = label_components(g.nx, g.ny, wet, label);
  FillResult r;
  r.out = std::make_shared<Heightfield>(in.domain);
  std::vector<float>& out = r.out->data;
  const FlatMode mode = p.epsilon ? FlatMode::Epsilon : FlatMode::Flat;
  std::vector<std::uint8_t> keep(static_cast<std::size_t>(count) + 1, 1);
  keep[0] = 0;
  if (!p.carve) {
    out = p.epsilon ? std::move(eps) : flat;
  } else {
    // Depressions no deeper than max_depth stay as (filled) lakes; the others are breached.
    std::vector<float> deepest(static_cast<std::size_t>(count) + 1, 0.0f);
    for (std::size_t c = 0; c < flat.size(); ++c)
      if (label[c]) deepest[label[c]] = std::max(deepest[label[c]], flat[c] - in.data[c]);
    for (int l = 1; l <= count; ++l) keep[l] = deepest[l] <= p.max_depth;
    out = in.data;
    for (std::size_t c = 0; c < flat.size(); ++c)
      if (keep[label[c]]) out[c] = flat[c];
    breach_depressions(g, out, mode, {}, ctx);  // epsilon: already its own epsilon fill
  }
  if (!p.lake_maps) return r;
  r.depth = std::make_shared<Heightfield>(in.domain);
  r.lake_id = std::make_shared<Heightfield>(in.domain);
  // Renumber the kept lakes 1..n in order.
  std::vector<std::int32_t> renum(static_cast<std::size_t>(count) + 1, 0);
  int lakes = 0;
  for (int l = 1; l <= count; ++l)
    if (keep[l]) renum[l] = ++lakes;
  for (std::size_t c = 0; c < flat.size(); ++c) {
    const std::int32_t id = renum[label[c]];
    r.lake_id->data[c] = static_cast<float>(id);
    r.depth->data[c] = id ? flat[c] - in.data[c] : 0.0f;
  }
  r.lakes = lakes;
  return r;
}

FillResult lakes(const Heightfield& in, const LakesParams& p, const ExecContext* ctx) {
  const FlowGrid g = FlowGrid::of(in.domain);
  const std::vector<float> flat = flat_filled(in, ctx);
  std::vector<std::uint8_t> wet(flat.size());
  for (std::size_t c = 0; c < flat.size(); ++c) wet[c] = flat[c] > in.data[c];
  std::vector<std::int32_t> label;
  const int count = label_components(g.nx, g.ny, wet, label);
  std::vector<float> deepest(static_cast<std::size_t>(count) + 1, 0.0f);
  std::vector<std::size_t> cells(static_cast<std::size_t>(count) + 1, 0);
  for (std::size_t c = 0; c < flat.size(); ++c)
    if (label[c]) {
      deepest[label[c]] = std::max(deepest[label[c]], flat[c] - in.data[c]);
      ++cells[label[c]];
    }
  std::vector<std::int32_t> renum(static_cast<std::size_t>(count) + 1, 0);
  int n = 0;
  for (int l = 1; l <= count; ++l)
    if (deepest[l] >= p.min_depth && static_cast<double>(cells[l]) * g.cell_area() >= p.min_area) renum[l] = ++n;
  FillResult r;
  r.out = std::make_shared<Heightfield>(in);
  if (p.lake_maps) {
    r.depth = std::make_shared<Heightfield>(in.domain);
    r.lake_id = std::make_shared<Heightfield>(in.domain);
  }
  for (std::size_t c = 0; c < flat.size(); ++c) {
    const std::int32_t id = renum[label[c]];
    if (!id) continue;
    r.out->data[c] = flat[c];
    if (!p.lake_maps) continue;
    r.depth->data[c] = flat[c] - in.data[c];
    r.lake_id->data[c] = static_cast<float>(id);
  }
  r.lakes = n;
  return r;
}

FloodFillResult flood_fill(const Heightfield& in, const FloodFillParams& p, const ExecContext* ctx) {
  const FlowGrid g = FlowGrid::of(in.domain);
  const glm::dvec2 s = in.domain.to_sample(p.seed);
  const int si = std::clamp(static_cast<int>(std::lround(s.x)), 0, g.nx - 1);
  const int sj = std::clamp(static_cast<int>(std::lround(s.y)), 0, g.ny - 1);
  const std::int32_t seed = g.index(si, sj);
  FloodFillResult r;
  r.level = p.spill ? static_cast<double>(flat_filled(in, ctx)[static_cast<std::size_t>(seed)]) : p.level;
  const float level = static_cast<float>(r.level);
  r.out = std::make_shared<Heightfield>(in);
  r.depth = std::make_shared<Heightfield>(in.domain);
  r.mask = std::make_shared<Heightfield>(in.domain);
  if (!(in.data[seed] < level)) return r;
  std::vector<std::uint8_t> seen(g.size(), 0);
  std::vector<std::int32_t> queue{seed};
  seen[seed] = 1;
  for (std::size_t h = 0; h < queue.size(); ++h) {
    const std::int32_t c = queue[h];
    r.out->data[c] = level;
    r.depth->data[c] = level - in.data[c];
    r.mask->data[c] = 1.0f;
    const int i = g.column(c), j = g.row(c);
    for (int k = 0; k < 8; ++k) {
      const int ii = i + kDi[k], jj = j + kDj[k];
      if (!g.inside(ii, jj)) continue;
      const std::int32_t n = g.index(ii, jj);
      if (!seen[n] && in.data[n] < level) {
        seen[n] = 1;
        queue.push_back(n);
      }
    }
    if ((h & 0xFFFF) == 0 && ctx) ctx->check_cancelled();
  }
  return r;
}

// Whether FillDepressions' or Lakes' depth or lake id map is linked (or the node requested whole).
static bool lake_maps_requested(const ExecContext& ctx) {
  return ctx.output_requested("water_depth") || ctx.output_requested("lake_id");
}

// The three outputs FillDepressions and Lakes share: water surface (or filled ground), depth and lake id; the
// maps only when computed (lake_maps), since nothing uses them otherwise.
static void set_fill_outputs(ExecContext& ctx, const FillResult& r) {
  ctx.set_output("out", r.out);
  if (r.depth) ctx.set_output("water_depth", r.depth);
  if (r.lake_id) ctx.set_output("lake_id", r.lake_id);
}

OROGEN_NODE(FillDepressions) {
  b.version(2);  // 2: carving down the D8 tree of the epsilon surface (tile-exact), not the Priority-Flood's backlinks
  b.distribution(Distribution::TileGraph);
  b.reach_global();  // flow routing over the whole domain
  b.category("hydrology")
      .description(
          "Removes closed depressions so every cell drains to the border: Priority-Flood (Barnes, Lehman & Mulla "
          "2014, 'Priority-Flood: an optimal depression-filling and watershed-labeling algorithm') with the slope "
          "and depression queues of Zhou, Sun & Fu 2016. 'fill' raises each depression to its spill level; 'carve' "
          "cuts a channel from each pit through the rim instead (complete breaching, Lindsay 2016: down the D8 path "
          "of the epsilon surface, every cell higher than the pit lowered to it), keeping depressions no deeper "
          "than max_depth as filled lakes; tiles and ranks carve the same channels. 'epsilon' flats rise by one "
          "float ulp per cell away from their outlet so every cell has a strictly lower neighbor (flow routing needs "
          "it): each cell is max(its height, one ulp above its lowest neighbor), the least such surface, which "
          "depends on the heights alone (so tiles reproduce it exactly); 'flat' leaves them level. The lakes (filled "
          "water, from the flat levels in either case) come out as a depth and an id per lake.");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.output("out", PortType::Heightfield).description("Filled or carved height, metres");
  b.output("water_depth", PortType::Heightfield)
      .unit(Unit::Metre)
      .description("Water depth of the kept lakes (flat surface minus ground), metres")
      .kind(OutputKind::WaterDepth);
  b.output("lake_id", PortType::Heightfield)
      .description("Lake number 1, 2, ... (row-major order of first cell), 0 on dry ground")
      .kind(OutputKind::Scalar);
  b.param_enum("mode", {"fill", "carve"}, "fill")
      .description("fill: raise depressions to their spill level; carve: breach a channel out of them");
  b.param_enum("flats", {"epsilon", "flat"}, "epsilon")
      .description("epsilon: filled areas drain with a minimal gradient; flat: filled areas are exactly level");
  b.param_float("max_depth", 0.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 100.0)
      .unit(Unit::Metre)
      .description("carve mode: depressions at most this deep are filled and kept as lakes, deeper ones are carved");
  // Working memory beyond the outputs, 8 bytes a sample filling (calibrated on its measured peak:
  // tests/test_peak_memory.cpp); carving holds the epsilon surface, the D8 tree, its order, the pits and the values
  // carried down, 20 (measured at 4097^2: 459 MB against 227 MB filling).
  b.extra_bytes(
      [](const CostQuery& q) { return per_sample_bytes(q, q.params.get<std::string>("mode") == "carve" ? 20 : 8); });
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const FillParams p{ctx.enum_index("mode") == 1, ctx.enum_index("flats") == 0, ctx.param<double>("max_depth"),
                       lake_maps_requested(ctx)};
    set_fill_outputs(ctx, fill_depressions(*in, p, &ctx));
  });
}

OROGEN_NODE(Lakes) {
  b.distribution(Distribution::TileGraph);
  b.reach_global();  // flow routing over the whole domain
  b.category("hydrology")
      .description(
          "Every closed depression as a lake filled to its spill level (Priority-Flood, Barnes, Lehman & Mulla 2014): "
          "a flat water surface, its depth and a lake id; depressions shallower than min_depth or smaller than "
          "min_area stay dry.");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.output("out", PortType::Heightfield).description("Water surface on lakes, ground elsewhere, metres");
  b.output("water_depth", PortType::Heightfield)
      .unit(Unit::Metre)
      .description("Water depth, metres")
      .kind(OutputKind::WaterDepth);
  b.output("lake_id", PortType::Heightfield)
      .description("Lake number 1, 2, ..., 0 on dry ground")
      .kind(OutputKind::Scalar);
  b.param_float("min_depth", 0.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 50.0)
      .unit(Unit::Metre)
      .description("Depressions whose deepest point is shallower than this are not lakes");
  b.param_float("min_area", 0.0)
      .range(0.0, 1e12)
      .soft_range(0.0, 1e6)
      .unit(Unit::SquareMetre)
      .description("Depressions covering less than this area are not lakes");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const LakesParams p{ctx.param<double>("min_depth"), ctx.param<double>("min_area"), lake_maps_requested(ctx)};
    set_fill_outputs(ctx, lakes(*in, p, &ctx));
  });
}

OROGEN_NODE(FloodFill) {
  b.distribution(Distribution::TileGraph);
  b.reach_global();  // flow routing over the whole domain
  b.category("hydrology")
      .description(
          "A lake from a seed point (Long 2016, 'Using procedural methods to generate realistic virtual rural worlds', "
          "section 3.4): every cell 8-connected to the seed "
          "whose ground lies below the water level is flooded, with a flat surface. The level is given, or is the "
          "spill level of the seed's depression (the lowest rim point, from Priority-Flood, Barnes et al. 2014).");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.output("out", PortType::Heightfield).description("Water surface in the lake, ground elsewhere, metres");
  b.output("water_depth", PortType::Heightfield)
      .unit(Unit::Metre)
      .description("Water depth, metres (0 outside the lake)")
      .kind(OutputKind::WaterDepth);
  b.output("lake_mask", PortType::Heightfield)
      .unit(Unit::Unitless)
      .description("1 in the lake, 0 elsewhere")
      .kind(OutputKind::Mask);
  b.param_vec2("position", glm::dvec2(0.0, 0.0))
      .range(-1e7, 1e7)
      .unit(Unit::Metre)
      .description("World position the lake grows from");
  b.param_enum("level_mode", {"spill", "level"}, "spill")
      .description("spill: fill to the depression's spill level; level: fill to the given level");
  b.param_float("level", 0.0)
      .range(-1e5, 1e5)
      .soft_range(-100.0, 1000.0)
      .unit(Unit::Metre)
      .description("Water level in level mode");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const FloodFillParams p{ctx.param<glm::dvec2>("position"), ctx.enum_index("level_mode") == 0,
                            ctx.param<double>("level")};
    FloodFillResult r = flood_fill(*in, p, &ctx);
    ctx.set_output("out", r.out);
    ctx.set_output("water_depth", r.depth);
    ctx.set_output("lake_mask", r.mask);
  });
}

}  // namespace orogen::hydrology
