// Terrace node.
#include "nodes/field/terrace.h"

#include "graph/registry.h"
#include "nodes/field/field_map.h"

namespace orogen {

OROGEN_NODE(Terrace) {
  b.reach_pointwise();
  b.category("field").description(
      "Stepped terraces (mesas, rice paddies, strata). mode 'count': `levels` equal steps between range_min and "
      "range_max, identity outside; mode 'spacing': a level every `spacing` metres starting at `offset`, "
      "everywhere. Within a step the riser is u^(1/(1-sharpness)) of the step: 0 keeps the input, 1 gives "
      "flat treads and vertical risers. The result never decreases where the input increases.");
  b.input("in", PortType::Heightfield).description("Heights");
  b.output("out", PortType::Heightfield).description("Terraced heights");
  b.param_enum("mode", {"count", "spacing"}, "count").description("How levels are placed");
  b.param_int("levels", 10)
      .unit(Unit::Count)
      .range(1, 10000)
      .soft_range(1, 64)
      .description("count mode: number of steps in the range");
  b.param_float("range_min", 0.0)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .unit(Unit::Metre)
      .description("count mode: lowest level");
  b.param_float("range_max", 1000.0)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .unit(Unit::Metre)
      .description("count mode: highest level (> range_min)");
  b.param_float("spacing", 10.0)
      .range(1e-6, 1e6)
      .soft_range(0.5, 500)
      .unit(Unit::Metre)
      .description("spacing mode: height between levels");
  b.param_float("offset", 0.0)
      .range(-1e6, 1e6)
      .soft_range(-500, 500)
      .unit(Unit::Metre)
      .description("spacing mode: height of one level");
  b.param_float("sharpness", 0.7).unit(Unit::Unitless).range(0.0, 1.0).description("0 = no terracing, 1 = hard steps");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const double s = ctx.param<double>("sharpness");
    if (ctx.param<std::string>("mode") == "count") {
      const double lo = ctx.param<double>("range_min"), hi = ctx.param<double>("range_max");
      if (!(hi > lo)) throw NodeError("Terrace: range_max must be greater than range_min");
      const int levels = static_cast<int>(ctx.param<std::int64_t>("levels"));
      ctx.set_output("out", map_field(
                                *in, [=](double h) { return terrace_in_range(h, lo, hi, levels, s); }, &ctx));
    } else {
      const TerraceParams p{ctx.param<double>("offset"), ctx.param<double>("spacing"), s};
      ctx.set_output("out", map_field(
                                *in, [&](double h) { return terrace_value(h, p); }, &ctx));
    }
  });
}

}  // namespace orogen
