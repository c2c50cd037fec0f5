// Power node (Weiss 2015 Eq 3).
#include "nodes/field/power.h"

#include <cmath>
#include <limits>
#include <string>

#include "graph/registry.h"
#include "nodes/field/field_map.h"

namespace orogen {

OROGEN_NODE(Power) {
  b.reach_pointwise();
  b.category("field").description(
      "Sign-preserving power about a pivot: out = pivot + scale * sign(t) * |t|^exponent, t = (h - pivot) / "
      "scale. With pivot 0, scale 1 and exponent 1.5 it is the elevation redistribution of A. Patel (2015), "
      "\"Making maps with noise functions\", Red Blob Games. exponent > 1 flattens values near the pivot "
      "and exaggerates those beyond scale; < 1 the opposite. Values at pivot and pivot +- scale are fixed.");
  b.input("in", PortType::Heightfield).description("Field");
  b.output("out", PortType::Heightfield).description("Reshaped field");
  b.param_float("exponent", 1.5)
      .unit(Unit::Unitless)
      .range(0.01, 20.0)
      .soft_range(0.25, 4.0)
      .description("Exponent p (1 = identity)");
  b.param_float("pivot", 0.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Value the power is taken about, in the input's units");
  b.param_float("scale", 1.0)
      .unit(Unit::InputUnits)
      .range(1e-6, 1e6)
      .soft_range(0.01, 1000)
      .description(
          "Distance from the pivot that stays fixed, in the input's units: values are divided by it before the power");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const PowerParams p{ctx.param<double>("exponent"), ctx.param<double>("pivot"), ctx.param<double>("scale")};
    // A finite height whose power leaves the float range is refused, naming what to change, rather than stored
    // as an infinity (heights of a few hundred metres at scale 1 overflow from an exponent of about 15).
    auto power = [&](double h) {
      const double v = power_value(h, p);
      if (std::isfinite(h) && !(std::abs(v) <= std::numeric_limits<float>::max()))
        throw NodeError("Power: " + std::to_string(h) + " gives " + std::to_string(v) +
                        ", beyond the range of a float (3.4e38): lower 'exponent' or raise 'scale'");
      return v;
    };
    ctx.set_output("out", map_field(*in, power, &ctx));
  });
}

}  // namespace orogen
