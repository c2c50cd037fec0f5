// Invert, Abs, Clamp: the simplest sample-wise transforms of one field.
#include <algorithm>
#include <cmath>

#include "graph/registry.h"
#include "nodes/field/field_map.h"

namespace orogen {

OROGEN_NODE(Invert) {
  b.reach_pointwise();
  b.category("field").description(
      "Mirrors heights about a pivot: out = 2 * pivot - h (pivot 0 gives -h). "
      "Turns ridges into valleys and a 0..1 mask m into 1 - m with pivot 0.5.");
  b.input("in", PortType::Heightfield).description("Field to invert");
  b.output("out", PortType::Heightfield).description("2 * pivot - in");
  b.param_float("pivot", 0.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Value that stays fixed, in the input's units; 0.5 inverts a 0..1 mask");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const double two_pivot = 2.0 * ctx.param<double>("pivot");
    ctx.set_output("out", map_field(
                              *in, [=](double h) { return two_pivot - h; }, &ctx));
  });
}

OROGEN_NODE(Abs) {
  b.reach_pointwise();
  b.category("field").description("Absolute value |h| of every sample (folds valleys up into ridges).");
  b.input("in", PortType::Heightfield).description("Field");
  b.output("out", PortType::Heightfield).description("|in|");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    ctx.set_output("out", map_field(
                              *in, [](double h) { return std::abs(h); }, &ctx));
  });
}

OROGEN_NODE(Clamp) {
  b.reach_pointwise();
  b.category("field").description("Limits every sample to [min, max].");
  b.input("in", PortType::Heightfield).description("Field to clamp");
  b.output("out", PortType::Heightfield).description("min(max(in, min), max)");
  b.param_float("min", 0.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Lower bound, in the input's units");
  b.param_float("max", 1.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Upper bound (>= min), in the input's units");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const double lo = ctx.param<double>("min"), hi = ctx.param<double>("max");
    if (lo > hi) throw NodeError("Clamp: min (" + std::to_string(lo) + ") is above max (" + std::to_string(hi) + ")");
    ctx.set_output("out", map_field(
                              *in, [=](double h) { return std::clamp(h, lo, hi); }, &ctx));
  });
}

}  // namespace orogen
