#include "nodes/landform/crater.h"

#include <cmath>

#include "graph/registry.h"
#include "nodes/field/field_map.h"
#include "nodes/landform/landform_common.h"

namespace orogen {

using landform::num;
using landform::require;

void check_crater(const CraterParams& p) {
  require(p.radius > 0.0, "Crater", "radius (" + num(p.radius) + " m) must be positive");
  require(
      p.floor_radius >= 0.0 && p.floor_radius < p.radius, "Crater",
      "floor_radius (" + num(p.floor_radius) + " m) must be at least 0 and less than radius (" + num(p.radius) + " m)");
  require(p.depth >= 0.0, "Crater", "depth (" + num(p.depth) + " m) must be at least 0");
  require(p.rim_height >= 0.0, "Crater", "rim_height (" + num(p.rim_height) + " m) must be at least 0");
  require(p.ejecta_exponent > 0.0, "Crater", "ejecta_exponent (" + num(p.ejecta_exponent) + ") must be positive");
}

double crater_height(const CraterParams& p, double x, double y) {
  const double r = std::hypot(x - p.position.x, y - p.position.y);
  if (r > p.radius) return p.base_height + p.rim_height * std::pow(r / p.radius, -p.ejecta_exponent);
  if (r <= p.floor_radius) return p.base_height - p.depth;
  const double s = (r - p.floor_radius) / (p.radius - p.floor_radius);
  return p.base_height - p.depth + (p.depth + p.rim_height) * s * s;
}

std::shared_ptr<Heightfield> crater_field(const Domain& domain, const CraterParams& p, const ExecContext* ctx) {
  check_crater(p);
  return generate_field(
      domain, [&](double x, double y) { return crater_height(p, x, y); }, ctx);
}

OROGEN_NODE(Crater) {
  b.reach_pointwise();
  b.category("landform")
      .description(
          "An impact crater on a level surface at base_height: a bowl (flat floor within floor_radius) `depth` "
          "below the surface, rising as the square of the distance to a rim crest rim_height above it at "
          "`radius`, and an ejecta blanket beyond that thins as (r / radius)^-ejecta_exponent. Proportions after "
          "R. Pike (1977), \"Size-dependence in the shape of fresh impact craters on the Moon\", Impact and "
          "Explosion Cratering (depth about 0.2 and rim height about 0.04 of the diameter for simple craters); "
          "ejecta exponent 3 after T. McGetchin, M. Settle and J. Head (1973), \"Radial thickness variation in "
          "impact crater ejecta\", Earth and Planetary Science Letters 20.");
  b.output("out", PortType::Heightfield).description("Heights, metres").kind(OutputKind::Height).unit(Unit::Metre);
  b.param_vec2("position", {512.0, 512.0})
      .range(-1e7, 1e7)
      .unit(Unit::Metre)
      .description("World position of the center");
  b.param_float("radius", 200.0)
      .range(1e-3, 1e7)
      .soft_range(10.0, 10000.0)
      .unit(Unit::Metre)
      .description("Radius of the rim crest (half the crater's diameter)");
  b.param_float("depth", 80.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 2000.0)
      .unit(Unit::Metre)
      .description("Depth of the floor below base_height (about 0.2 of the diameter for a fresh simple crater)");
  b.param_float("rim_height", 16.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 500.0)
      .unit(Unit::Metre)
      .description("Height of the rim crest above base_height (about 0.04 of the diameter)");
  b.param_float("floor_radius", 0.0)
      .range(0.0, 1e7)
      .soft_range(0.0, 5000.0)
      .unit(Unit::Metre)
      .description("Radius of a flat floor (complex craters); 0 for a bowl. Must be less than radius");
  b.param_float("ejecta_exponent", 3.0)
      .range(0.1, 20.0)
      .soft_range(1.0, 8.0)
      .unit(Unit::Unitless)
      .description("How fast the ejecta thin beyond the rim: height rim_height (r / radius)^-exponent");
  b.param_float("base_height", 0.0)
      .range(-1e5, 1e5)
      .soft_range(-2000.0, 2000.0)
      .unit(Unit::Metre)
      .description("Height of the surrounding surface, reached far from the crater");
  b.execute([](ExecContext& ctx) {
    CraterParams p;
    p.position = ctx.param<glm::dvec2>("position");
    p.radius = ctx.param<double>("radius");
    p.depth = ctx.param<double>("depth");
    p.rim_height = ctx.param<double>("rim_height");
    p.floor_radius = ctx.param<double>("floor_radius");
    p.ejecta_exponent = ctx.param<double>("ejecta_exponent");
    p.base_height = ctx.param<double>("base_height");
    ctx.set_output("out", crater_field(ctx.domain(), p, &ctx));
  });
}

}  // namespace orogen
