// SmoothStep and Threshold nodes.
#include "nodes/field/smoothstep.h"

#include "graph/registry.h"
#include "nodes/field/field_map.h"

namespace orogen {

OROGEN_NODE(SmoothStep) {
  b.reach_pointwise();
  b.category("field").description(
      "Soft threshold: 0 below edge0, 1 above edge1, a smooth Hermite ramp t^2 (3 - 2t) between. "
      "edge0 > edge1 gives a falling mask; equal edges a hard step.");
  b.input("in", PortType::Heightfield).description("Field (e.g. heights in metres)");
  b.output("out", PortType::Heightfield).description("Mask in 0..1").kind(OutputKind::Mask);
  b.param_float("edge0", 0.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Value where the mask is 0, in the input's units");
  b.param_float("edge1", 100.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Value where the mask is 1, in the input's units");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const double e0 = ctx.param<double>("edge0"), e1 = ctx.param<double>("edge1");
    ctx.set_output("out", map_field(
                              *in, [=](double h) { return smoothstep_value(h, e0, e1); }, &ctx));
  });
}

OROGEN_NODE(Threshold) {
  b.reach_pointwise();
  b.category("field").description(
      "Hard threshold: 1 where the value is at or above `level`, else 0 (or the "
      "reverse with invert).");
  b.input("in", PortType::Heightfield).description("Field (e.g. heights in metres)");
  b.output("out", PortType::Heightfield).description("Mask of 0 and 1").kind(OutputKind::Mask);
  b.param_float("level", 0.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Threshold value, in the input's units");
  b.param_bool("invert", false).description("1 below the level instead of above");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const double level = ctx.param<double>("level");
    const double above = ctx.param<bool>("invert") ? 0.0 : 1.0;
    ctx.set_output("out", map_field(
                              *in, [=](double h) { return h >= level ? above : 1.0 - above; }, &ctx));
  });
}

}  // namespace orogen
