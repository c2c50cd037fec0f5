// Remap node: a field's values linearly from [in_min, in_max] to [out_min, out_max].
#include "nodes/field/remap.h"

#include "graph/registry.h"
#include "nodes/field/field_map.h"

namespace orogen {

OROGEN_NODE(Remap) {
  b.reach_pointwise();
  b.category("field").description(
      "Maps values linearly from an input range to an output range: in_min -> out_min, in_max -> out_max "
      "(reversed ranges invert). Values outside the input range extrapolate unless clamp is on.");
  b.input("in", PortType::Heightfield).description("Field to remap");
  b.output("out", PortType::Heightfield).description("Remapped field");
  b.param_float("in_min", 0.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Input value mapped to out_min, in the input's units");
  b.param_float("in_max", 1.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Input value mapped to out_max (!= in_min), in the input's units");
  b.param_float("out_min", 0.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Output for in_min (unit of your choosing: metres for heights, unitless for masks)");
  b.param_float("out_max", 1.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Output for in_max");
  b.param_bool("clamp", false).description("Clamp the result to the output range");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const RemapRange r{ctx.param<double>("in_min"), ctx.param<double>("in_max"), ctx.param<double>("out_min"),
                       ctx.param<double>("out_max"), ctx.param<bool>("clamp")};
    if (r.in_min == r.in_max) throw NodeError("Remap: the input range is empty (in_min == in_max)");
    ctx.set_output("out", map_field(
                              *in, [&](double h) { return remap_value(h, r); }, &ctx));
  });
}

}  // namespace orogen
