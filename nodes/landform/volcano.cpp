#include "nodes/landform/volcano.h"

#include <cmath>

#include "graph/registry.h"
#include "nodes/field/field_map.h"
#include "nodes/landform/landform_common.h"

namespace orogen {

using landform::num;
using landform::require;

void check_volcano(const VolcanoParams& p) {
  require(p.radius > 0.0, "Volcano", "radius (" + num(p.radius) + " m) must be positive");
  require(p.crater_radius >= 0.0 && p.crater_radius < p.radius, "Volcano",
          "crater_radius (" + num(p.crater_radius) + " m) must be at least 0 and less than radius (" + num(p.radius) +
              " m)");
  require(p.flank_exponent > 0.0, "Volcano", "flank_exponent (" + num(p.flank_exponent) + ") must be positive");
  require(p.crater_depth >= 0.0, "Volcano", "crater_depth (" + num(p.crater_depth) + " m) must be at least 0");
}

double volcano_height(const VolcanoParams& p, double x, double y) {
  const double r = std::hypot(x - p.position.x, y - p.position.y);
  if (r >= p.radius) return 0.0;
  if (r > p.crater_radius) return p.height * std::pow((p.radius - r) / (p.radius - p.crater_radius), p.flank_exponent);
  const double u = r / p.crater_radius;  // crater_radius > 0 here, since r <= crater_radius and r >= 0
  return p.height - p.crater_depth * (1.0 - u * u);
}

std::shared_ptr<Heightfield> volcano_field(const Domain& domain, const VolcanoParams& p, const ExecContext* ctx) {
  check_volcano(p);
  return generate_field(
      domain, [&](double x, double y) { return volcano_height(p, x, y); }, ctx);
}

OROGEN_NODE(Volcano) {
  b.reach_pointwise();
  b.category("landform")
      .description(
          "A volcano: a cone of base `radius` whose flanks rise as ((radius - r) / (radius - crater_radius))^"
          "flank_exponent to the rim at `height`, with a paraboloid summit crater whose floor lies crater_depth "
          "below the rim; 0 beyond the base. flank_exponent 1, crater_radius about 0.4 radius and height about 0.36 "
          "radius gives the straight-flanked cinder cone of C. A. Wood (1980), \"Morphometric "
          "evolution of cinder cones\", Journal of Volcanology and Geothermal Research 7; exponents above 1 give "
          "the concave flanks of stratovolcanoes. Add it to a terrain with Add or Max.");
  b.output("out", PortType::Heightfield).description("Heights, metres").kind(OutputKind::Height).unit(Unit::Metre);
  b.param_vec2("position", {512.0, 512.0})
      .range(-1e7, 1e7)
      .unit(Unit::Metre)
      .description("World position of the summit (center of the crater)");
  b.param_float("radius", 500.0)
      .range(1e-3, 1e7)
      .soft_range(50.0, 10000.0)
      .unit(Unit::Metre)
      .description("Base radius: the flanks reach 0 here");
  b.param_float("height", 250.0)
      .range(-1e5, 1e5)
      .soft_range(0.0, 4000.0)
      .unit(Unit::Metre)
      .description("Height of the crater rim, the highest ring of the volcano");
  b.param_float("flank_exponent", 1.5)
      .range(0.1, 10.0)
      .soft_range(0.5, 4.0)
      .unit(Unit::Unitless)
      .description("Flank profile: 1 straight, above 1 concave (steepening toward the rim), below 1 a convex dome");
  b.param_float("crater_radius", 60.0)
      .range(0.0, 1e7)
      .soft_range(0.0, 2000.0)
      .unit(Unit::Metre)
      .description("Radius of the summit crater at its rim; 0 for a pointed cone. Must be less than radius");
  b.param_float("crater_depth", 50.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 1000.0)
      .unit(Unit::Metre)
      .description("Depth of the crater floor below the rim");
  b.execute([](ExecContext& ctx) {
    VolcanoParams p;
    p.position = ctx.param<glm::dvec2>("position");
    p.radius = ctx.param<double>("radius");
    p.height = ctx.param<double>("height");
    p.flank_exponent = ctx.param<double>("flank_exponent");
    p.crater_radius = ctx.param<double>("crater_radius");
    p.crater_depth = ctx.param<double>("crater_depth");
    ctx.set_output("out", volcano_field(ctx.domain(), p, &ctx));
  });
}

}  // namespace orogen
