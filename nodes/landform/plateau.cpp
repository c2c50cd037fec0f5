#include "nodes/landform/plateau.h"

#include <algorithm>
#include <cmath>

#include "graph/cost_query.h"
#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/landform/landform_common.h"

namespace orogen {

using landform::num;
using landform::require;

namespace {
constexpr int kEdgeOctaves = 4;
}

void check_plateau(const PlateauParams& p) {
  require(p.radius > 0.0, "Plateau", "radius (" + num(p.radius) + " m) must be positive");
  require(p.escarpment_width > 0.0, "Plateau", "escarpment_width (" + num(p.escarpment_width) + " m) must be positive");
  require(p.edge_roughness >= 0.0, "Plateau", "edge_roughness (" + num(p.edge_roughness) + " m) must be at least 0");
  require(p.edge_feature_size > 0.0, "Plateau",
          "edge_feature_size (" + num(p.edge_feature_size) + " m) must be positive");
}

std::shared_ptr<Heightfield> plateau_field(const Domain& domain, const PlateauParams& p, const ExecContext* ctx) {
  check_plateau(p);
  // The outline's noise as a field on the same lattice (world-space, so tiles agree); skipped when unused.
  Heightfield edge;
  if (p.edge_roughness > 0.0)
    edge = landform::unit_noise(domain, p.edge_feature_size, kEdgeOctaves, false, p.seed, ctx);
  auto out = std::make_shared<Heightfield>(domain);
  for_each_row(ctx, domain.height(), [&](int j) {
    const double y = domain.y(j);
    auto o = out->row(j);
    for (int i = 0; i < domain.width(); ++i) {
      const double r = std::hypot(domain.x(i) - p.position.x, y - p.position.y);
      const double n = p.edge_roughness > 0.0 ? static_cast<double>(edge.at(i, j)) : 0.0;
      const double t = std::clamp((r + p.edge_roughness * n - p.radius) / p.escarpment_width, 0.0, 1.0);
      o[static_cast<std::size_t>(i)] = static_cast<float>(p.base_height + p.height * (1.0 - t) * (1.0 - t));
    }
  });
  return out;
}

OROGEN_NODE(Plateau) {
  b.reach_pointwise();
  // The noise fields held beside the output while it is filled.
  b.extra_bytes(
      [](const CostQuery& q) { return per_sample_bytes(q, q.params.get<double>("edge_roughness") > 0.0 ? 4.0 : 0.0); });
  b.category("landform")
      .description(
          "A plateau or mesa: a flat top at base_height + height within `radius` of `position`, an escarpment "
          "escarpment_width wide falling as height (1 - t)^2 (t from 0 at the brink to 1 at the foot: a sharp "
          "caprock brink, slope atan(2 height / escarpment_width), over a concave talus), and base_height "
          "beyond. A seeded fBm (K. Perlin (2002), \"Improving noise\", SIGGRAPH) moves the outline in and out "
          "by up to edge_roughness.");
  b.output("out", PortType::Heightfield).description("Heights, metres").kind(OutputKind::Height).unit(Unit::Metre);
  b.param_vec2("position", {512.0, 512.0})
      .range(-1e7, 1e7)
      .unit(Unit::Metre)
      .description("World position of the center");
  b.param_float("radius", 250.0)
      .range(1e-3, 1e7)
      .soft_range(10.0, 10000.0)
      .unit(Unit::Metre)
      .description("Radius of the flat top, to the brink of the escarpment");
  b.param_float("height", 120.0)
      .range(-1e5, 1e5)
      .soft_range(0.0, 2000.0)
      .unit(Unit::Metre)
      .description("Height of the top above base_height");
  b.param_float("escarpment_width", 80.0)
      .range(1e-3, 1e7)
      .soft_range(1.0, 2000.0)
      .unit(Unit::Metre)
      .description("Horizontal width of the escarpment, from the brink to the foot");
  b.param_float("base_height", 0.0)
      .range(-1e5, 1e5)
      .soft_range(-2000.0, 2000.0)
      .unit(Unit::Metre)
      .description("Height of the plain around the plateau");
  b.param_float("edge_roughness", 40.0)
      .range(0.0, 1e6)
      .soft_range(0.0, 500.0)
      .unit(Unit::Metre)
      .description("How far the outline wanders in and out of the circle (fBm amplitude); 0 for a circle");
  b.param_float("edge_feature_size", 150.0)
      .range(1e-3, 1e7)
      .soft_range(10.0, 2000.0)
      .unit(Unit::Metre)
      .description("Size of the largest bays and spurs of the outline");
  b.param_seed("seed", 0).description("Random seed of the outline");
  b.execute([](ExecContext& ctx) {
    PlateauParams p;
    p.position = ctx.param<glm::dvec2>("position");
    p.radius = ctx.param<double>("radius");
    p.height = ctx.param<double>("height");
    p.escarpment_width = ctx.param<double>("escarpment_width");
    p.base_height = ctx.param<double>("base_height");
    p.edge_roughness = ctx.param<double>("edge_roughness");
    p.edge_feature_size = ctx.param<double>("edge_feature_size");
    p.seed = ctx.param<std::uint64_t>("seed");
    ctx.set_output("out", plateau_field(ctx.domain(), p, &ctx));
  });
}

}  // namespace orogen
