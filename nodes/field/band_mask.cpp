// BandMask node.
#include "nodes/field/band_mask.h"

#include "graph/registry.h"
#include "nodes/field/field_map.h"

namespace orogen {

OROGEN_NODE(BandMask) {
  b.reach_pointwise();
  b.category("field").description(
      "Mask of where a field lies in a band [min, max]: 1 inside, a smooth falloff outside, 0 beyond it. Feed "
      "heights for elevation rules, Slope for slope rules, and multiply masks to combine rules, as in the "
      "ecosystem rules of J. Hammes (2001), \"Modeling of ecosystems as a data source for real-time terrain "
      "rendering\", Digital Earth Moving, LNCS 2181. The falloff width is `falloff` in the field's units, or, "
      "when that is 0, (max - min) / sharpness (Hammes' sharpness: 2 fades over half the band width on each "
      "side).");
  b.input("in", PortType::Heightfield).description("Any field: heights (m), slope (deg), moisture, ...");
  b.output("out", PortType::Heightfield).description("Mask in 0..1").kind(OutputKind::Mask);
  b.param_float("min", 0.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Lower edge of the band, in the field's units");
  b.param_float("max", 100.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Upper edge of the band (>= min), in the field's units");
  b.param_float("sharpness", 2.0)
      .unit(Unit::Unitless)
      .range(0.0, 1e6)
      .soft_range(0.5, 50.0)
      .description("Crispness when falloff is 0: transition width = (max - min) / sharpness; 0 = hard edges");
  b.param_float("falloff", 0.0)
      .unit(Unit::InputUnits)
      .range(0.0, 1e6)
      .soft_range(0.0, 500.0)
      .description("Transition width on each side, in the field's units (overrides sharpness when > 0)");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    BandParams p{ctx.param<double>("min"), ctx.param<double>("max"), ctx.param<double>("falloff")};
    if (p.min > p.max) throw NodeError("BandMask: min is above max");
    if (p.falloff == 0.0) p.falloff = falloff_from_sharpness(p.min, p.max, ctx.param<double>("sharpness"));
    ctx.set_output("out", map_field(
                              *in, [&](double v) { return band_mask_value(v, p); }, &ctx));
  });
}

}  // namespace orogen
