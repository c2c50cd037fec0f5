#include "nodes/landform/ridge.h"

#include <algorithm>
#include <cmath>

#include "graph/registry.h"
#include "nodes/field/field_map.h"
#include "nodes/landform/landform_common.h"

namespace orogen {

using landform::num;
using landform::require;

void check_ridge(const RidgeParams& p) {
  const double length = std::hypot(p.end.x - p.start.x, p.end.y - p.start.y);
  require(
      length > 0.0, "Ridge",
      "start and end are the same point (" + num(p.start.x) + ", " + num(p.start.y) + ") m; a ridge needs a length");
  require(p.half_width > 0.0, "Ridge", "half_width (" + num(p.half_width) + " m) must be positive");
  require(p.sharpness >= 0.0 && p.sharpness <= 1.0, "Ridge", "sharpness (" + num(p.sharpness) + ") must be 0..1");
  require(p.taper_length >= 0.0, "Ridge", "taper_length (" + num(p.taper_length) + " m) must be at least 0");
}

double ridge_height(const RidgeParams& p, double x, double y) {
  const double dx = p.end.x - p.start.x, dy = p.end.y - p.start.y;
  const double length = std::hypot(dx, dy);
  // Along-segment distance of the nearest point, clamped to the segment.
  const double s = std::clamp(((x - p.start.x) * dx + (y - p.start.y) * dy) / length, 0.0, length);
  const double nx = p.start.x + dx * (s / length), ny = p.start.y + dy * (s / length);
  const double u = std::hypot(x - nx, y - ny) / p.half_width;
  if (u >= 1.0) return 0.0;
  const double bell = 1.0 - u * u * (3.0 - 2.0 * u);
  const double knife = (1.0 - u) * (1.0 - u);
  const double c = (1.0 - p.sharpness) * bell + p.sharpness * knife;
  const double a = p.taper_length > 0.0 ? landform::smoothstep01(std::min(s, length - s) / p.taper_length) : 1.0;
  return p.height * a * c;
}

std::shared_ptr<Heightfield> ridge_field(const Domain& domain, const RidgeParams& p, const ExecContext* ctx) {
  check_ridge(p);
  return generate_field(
      domain, [&](double x, double y) { return ridge_height(p, x, y); }, ctx);
}

OROGEN_NODE(Ridge) {
  b.reach_pointwise();
  b.category("landform")
      .description(
          "A ridge whose crest runs along the segment start-end at `height`, falling to 0 at half_width from it "
          "with the cross profile (1 - sharpness) (1 - 3u^2 + 2u^3) + sharpness (1 - u)^2, u = distance / "
          "half_width (a rounded bell blended with a knife-edge crest over concave flanks), and coming down to "
          "the ground over taper_length at each end (smoothstep of the distance to the nearer end).");
  b.output("out", PortType::Heightfield).description("Heights, metres").kind(OutputKind::Height).unit(Unit::Metre);
  b.param_vec2("start", {200.0, 300.0})
      .range(-1e7, 1e7)
      .unit(Unit::Metre)
      .description("World position of one end of the crest");
  b.param_vec2("end", {824.0, 724.0})
      .range(-1e7, 1e7)
      .unit(Unit::Metre)
      .description("World position of the other end of the crest");
  b.param_float("height", 200.0)
      .range(-1e5, 1e5)
      .soft_range(0.0, 3000.0)
      .unit(Unit::Metre)
      .description("Height of the crest");
  b.param_float("half_width", 150.0)
      .range(1e-3, 1e7)
      .soft_range(10.0, 5000.0)
      .unit(Unit::Metre)
      .description("Horizontal distance from the crest to the foot of either flank");
  b.param_float("sharpness", 0.6)
      .range(0.0, 1.0)
      .unit(Unit::Unitless)
      .description("Cross profile: 0 a rounded bell, 1 a knife-edge crest with concave flanks");
  b.param_float("taper_length", 150.0)
      .range(0.0, 1e7)
      .soft_range(0.0, 5000.0)
      .unit(Unit::Metre)
      .description("Length over which the crest comes down to the ground at each end; 0 for full-height ends");
  b.execute([](ExecContext& ctx) {
    RidgeParams p;
    p.start = ctx.param<glm::dvec2>("start");
    p.end = ctx.param<glm::dvec2>("end");
    p.height = ctx.param<double>("height");
    p.half_width = ctx.param<double>("half_width");
    p.sharpness = ctx.param<double>("sharpness");
    p.taper_length = ctx.param<double>("taper_length");
    ctx.set_output("out", ridge_field(ctx.domain(), p, &ctx));
  });
}

}  // namespace orogen
