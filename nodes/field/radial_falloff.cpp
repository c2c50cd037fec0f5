#include "nodes/field/radial_falloff.h"

#include <algorithm>
#include <cmath>

#include "graph/registry.h"
#include "nodes/common/match_domain.h"
#include "nodes/common/cancellable_rows.h"

namespace orogen {

CurveValue default_falloff_profile() { return {{{0.0, 1.0}, {0.3, 0.97}, {0.65, 0.6}, {1.0, 0.0}}}; }

double radial_falloff_value(glm::dvec2 position, double distance_offset, const RadialFalloffParams& p) {
  const double d = std::hypot(position.x - p.center.x, position.y - p.center.y) + distance_offset;
  return p.profile.evaluate(std::clamp(d / p.radius, 0.0, 1.0));
}

std::shared_ptr<Heightfield> radial_falloff(const Domain& domain, const RadialFalloffParams& p,
                                            const Heightfield* distance_offset, const ExecContext* ctx) {
  auto out = std::make_shared<Heightfield>(domain);
  for_each_row(ctx, domain.height(), [&](int j) {
    for (int i = 0; i < domain.width(); ++i) {
      const double off = distance_offset ? distance_offset->at(i, j) : 0.0;
      out->at(i, j) = static_cast<float>(radial_falloff_value(domain.position(i, j), off, p));
    }
  });
  return out;
}

OROGEN_NODE(RadialFalloff) {
  b.reach_pointwise();
  b.category("shape").description(
      "Island mask: profile(clamp(d / radius, 0, 1)) with d the distance from the center in metres, plus the "
      "optional distance_offset field (connect noise in metres for a ragged coastline). The default profile "
      "is 1 at the center, a plateau, a smooth shore and 0 from the radius on. Multiply heights by it, or "
      "subtract an offset scaled by its inverse, to sink the map's edges into the sea.");
  b.input("distance_offset", PortType::Heightfield)
      .optional()
      .description("Metres added to the distance from the center (resampled onto the requested domain)");
  b.output("out", PortType::Heightfield).description("Falloff mask, normally 0..1").kind(OutputKind::Mask);
  b.param_vec2("center", {512.0, 512.0}).range(-1e7, 1e7).unit(Unit::Metre).description("World position of the center");
  b.param_float("radius", 480.0)
      .range(1e-3, 1e7)
      .soft_range(10.0, 10000.0)
      .unit(Unit::Metre)
      .description("Distance at which the profile reaches its end (t = 1)");
  b.param_curve("profile", default_falloff_profile())
      .description("Mask as a function of normalized distance t = d / radius in 0..1");
  b.execute([](ExecContext& ctx) {
    const auto offset = secondary_input<Heightfield>(ctx, "distance_offset", ctx.domain());
    const RadialFalloffParams p{ctx.param<glm::dvec2>("center"), ctx.param<double>("radius"),
                                ctx.param<CurveValue>("profile")};
    ctx.set_output("out", radial_falloff(ctx.domain(), p, offset.get(), &ctx));
  });
}

}  // namespace orogen
