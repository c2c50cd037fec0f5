#include "nodes/field/curve_remap.h"

#include <algorithm>

#include "graph/registry.h"
#include "nodes/field/field_map.h"
#include "nodes/field/field_range.h"

namespace orogen {

double curve_remap_value(double h, const CurveValue& curve, double lo, double hi) {
  const double t = std::clamp((h - lo) / (hi - lo), 0.0, 1.0);
  return lo + curve.evaluate(t) * (hi - lo);
}

std::shared_ptr<Heightfield> curve_remap(const Heightfield& in, const CurveValue& curve, double lo, double hi,
                                         const ExecContext* ctx) {
  return map_field(
      in, [&](double h) { return curve_remap_value(h, curve, lo, hi); }, ctx);
}

OROGEN_NODE(Curve) {
  b.distribution(Distribution::Reduction);
  b.reach(
      [](const ParamView& p) { return p.get<std::string>("range") == "field" ? Reach::global() : Reach::pointwise(); },
      "point-wise; global with range = field");
  b.category("field").description(
      "Reshapes values through a monotone cubic curve (Fritsch-Carlson: no overshoot, monotone points give a "
      "monotone result). Values are normalized to t = (h - lo) / (hi - lo) in [0, 1], mapped through the curve "
      "(control points in the unit square) and scaled back to lo + curve(t) * (hi - lo). The range [lo, hi] is "
      "either fixed (input_min, input_max) or the field's own min and max. Values outside the range clamp.");
  b.input("in", PortType::Heightfield).description("Field to reshape");
  b.output("out", PortType::Heightfield).description("Reshaped field, inside [lo, hi]");
  b.param_curve("curve", CurveValue{{{0.0, 0.0}, {0.5, 0.3}, {1.0, 1.0}}})
      .description("Transfer curve on normalized values: x = input t, y = output t, both 0..1");
  b.param_enum("range", {"fixed", "field"}, "fixed")
      .description("fixed: normalize with input_min/input_max (tile-independent); field: with the field's min/max");
  b.param_float("input_min", 0.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("lo of the fixed range, in the input's units");
  b.param_float("input_max", 1000.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("hi of the fixed range (> input_min), in the input's units");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    double lo = ctx.param<double>("input_min"), hi = ctx.param<double>("input_max");
    if (ctx.param<std::string>("range") == "field") {
      const ValueRange r = field_range(*in, &ctx);
      lo = r.min;
      hi = r.max;
      if (r.empty || lo == hi) {  // flat field: nothing to reshape
        ctx.set_output("out", in);
        return;
      }
    } else if (!(hi > lo)) {
      throw NodeError("Curve: input_max must be greater than input_min");
    }
    ctx.set_output("out", curve_remap(*in, ctx.param<CurveValue>("curve"), lo, hi, &ctx));
  });
}

}  // namespace orogen
