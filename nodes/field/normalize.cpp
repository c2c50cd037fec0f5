#include "nodes/field/normalize.h"

#include <cmath>

#include "graph/registry.h"
#include "nodes/field/field_map.h"
#include "nodes/field/field_range.h"
#include "nodes/field/remap.h"

namespace orogen {

std::shared_ptr<Heightfield> normalize_field(const Heightfield& in, double lo, double hi, const ExecContext* ctx) {
  const ValueRange range = field_range(in, ctx);
  if (range.empty || range.min == range.max)
    return map_field(
        in, [=](double h) { return std::isnan(h) ? h : lo; }, ctx);
  const RemapRange r{range.min, range.max, lo, hi, true};
  return map_field(
      in, [&](double h) { return std::isnan(h) ? h : remap_value(h, r); }, ctx);
}

OROGEN_NODE(Normalize) {
  b.distribution(Distribution::Reduction);
  b.reach_global();  // the range of the whole domain
  b.category("field").description(
      "Stretches a field linearly so that its lowest sample becomes `min` and its highest `max` (a height "
      "range in metres, or 0..1 for a mask). Depends on the whole requested domain, so a tile and the full "
      "map normalize differently; use Remap with fixed ranges when tiles must match.");
  b.input("in", PortType::Heightfield).description("Field to normalize");
  b.output("out", PortType::Heightfield).description("Field spanning exactly [min, max]");
  b.param_float("min", 0.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Value of the lowest sample, in the input's units");
  b.param_float("max", 1.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Value of the highest sample, in the input's units");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    ctx.set_output("out", normalize_field(*in, ctx.param<double>("min"), ctx.param<double>("max"), &ctx));
  });
}

}  // namespace orogen
