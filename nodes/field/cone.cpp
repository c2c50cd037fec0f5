#include "nodes/field/cone.h"

#include <algorithm>
#include <cmath>

#include "graph/registry.h"
#include "nodes/field/field_map.h"

namespace orogen {

std::shared_ptr<Heightfield> cone_field(const Domain& domain, const ConeParams& p, const ExecContext* ctx) {
  return generate_field(
      domain,
      [&](double x, double y) {
        return p.height * std::max(0.0, 1.0 - std::hypot(x - p.center.x, y - p.center.y) / p.radius);
      },
      ctx);
}

OROGEN_NODE(Cone) {
  b.reach_pointwise();
  b.category("shape").description(
      "A cone: `height` at the center falling linearly to 0 at `radius` (slope atan(height / radius)), 0 "
      "beyond. A volcano or hill base shape; negative heights make a crater or basin.");
  b.output("out", PortType::Heightfield).description("Heights, metres").kind(OutputKind::Height);
  b.param_vec2("center", {512.0, 512.0}).range(-1e7, 1e7).unit(Unit::Metre).description("World position of the apex");
  b.param_float("radius", 400.0)
      .range(1e-3, 1e7)
      .soft_range(10.0, 10000.0)
      .unit(Unit::Metre)
      .description("Base radius");
  b.param_float("height", 200.0)
      .range(-1e5, 1e5)
      .soft_range(-2000.0, 2000.0)
      .unit(Unit::Metre)
      .description("Height of the apex");
  b.execute([](ExecContext& ctx) {
    const ConeParams p{ctx.param<glm::dvec2>("center"), ctx.param<double>("radius"), ctx.param<double>("height")};
    ctx.set_output("out", cone_field(ctx.domain(), p, &ctx));
  });
}

}  // namespace orogen
