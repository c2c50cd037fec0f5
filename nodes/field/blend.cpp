// Blend node.
#include "nodes/field/blend.h"

#include "graph/registry.h"
#include "nodes/field/field_map.h"
#include "nodes/common/match_domain.h"

namespace orogen {

OROGEN_NODE(Blend) {
  b.reach_pointwise();
  b.category("field").description(
      "Blends b into a: out = a + (m(a, b) - a) * factor * mask, with m = b (lerp), a + b (add), "
      "1 - (1 - a)(1 - b) (screen, for 0..1 masks) or max(a, b). Without a mask the weight is factor.");
  b.input("a", PortType::Heightfield).description("Base field; the result lies on its domain");
  b.input("b", PortType::Heightfield).description("Field blended in (resampled onto a's domain if it differs)");
  b.input("mask", PortType::Heightfield).optional().description("Per-sample weight, 0..1 (resampled onto a's domain)");
  b.output("out", PortType::Heightfield).description("Blended field");
  b.param_enum("mode", {"lerp", "add", "screen", "max"}, "lerp").description("How a and b combine");
  b.param_float("factor", 1.0)
      .unit(Unit::Unitless)
      .range(0.0, 1.0)
      .description("Global weight of b, multiplied by the mask");
  b.execute([](ExecContext& ctx) {
    const auto a = ctx.require<Heightfield>("a");
    const auto bf = require_secondary_input<Heightfield>(ctx, "b", a->domain);
    const auto mask = secondary_input<Heightfield>(ctx, "mask", a->domain);
    const auto mode = static_cast<BlendMode>(ctx.enum_index("mode"));
    const double factor = ctx.param<double>("factor");
    if (mask) {
      ctx.set_output(
          "out",
          map_fields(
              *a, *bf, *mask, [=](double x, double y, double m) { return blend_value(mode, x, y, factor * m); }, &ctx));
    } else {
      ctx.set_output("out", map_fields(
                                *a, *bf, [=](double x, double y) { return blend_value(mode, x, y, factor); }, &ctx));
    }
  });
}

}  // namespace orogen
