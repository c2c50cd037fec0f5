#include "nodes/field/warp.h"

#include "graph/registry.h"
#include "nodes/field/bicubic.h"
#include "nodes/common/match_domain.h"
#include "nodes/common/cancellable_rows.h"

namespace orogen {

std::shared_ptr<Heightfield> warp_field(const Heightfield& in, const Heightfield* dx, const Heightfield* dy,
                                        double strength, const ExecContext* ctx) {
  auto out = std::make_shared<Heightfield>(in.domain);
  const Domain& d = in.domain;
  for_each_row(ctx, d.height(), [&](int j) {
    auto o = out->row(j);
    for (int i = 0; i < d.width(); ++i) {
      const double ox = dx ? strength * dx->at(i, j) : 0.0;
      const double oy = dy ? strength * dy->at(i, j) : 0.0;
      // Offsets are converted to samples directly (not via world positions) so a zero offset hits the
      // sample exactly.
      o[static_cast<std::size_t>(i)] = static_cast<float>(catmull_rom(in, i + ox / d.spacing.x, j + oy / d.spacing.y));
    }
  });
  return out;
}

OROGEN_NODE(Warp) {
  b.distribution(Distribution::Gathered);
  b.reach_global();  // the displacement, read from the dx/dy fields, is unbounded
  b.category("field").description(
      "Domain warp by fields: out(x, y) = in(x + strength * dx, y + strength * dy), with the displacements in "
      "metres and bicubic (Catmull-Rom) lookups clamped at the edges. Feed noise into dx and dy for "
      "swirled, eroded-looking shapes. (Generators also warp exactly through their own warp inputs.)");
  b.input("in", PortType::Heightfield).description("Field to warp; the result lies on its domain");
  b.input("dx", PortType::Heightfield).optional().description("Displacement along world x, metres (0 if unconnected)");
  b.input("dy", PortType::Heightfield).optional().description("Displacement along world y, metres (0 if unconnected)");
  b.output("out", PortType::Heightfield).description("Warped field");
  b.param_float("strength", 1.0)
      .unit(Unit::Factor)
      .range(-1e3, 1e3)
      .soft_range(0.0, 4.0)
      .description("Multiplier of both displacements");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const auto dx = secondary_input<Heightfield>(ctx, "dx", in->domain);
    const auto dy = secondary_input<Heightfield>(ctx, "dy", in->domain);
    ctx.set_output("out", warp_field(*in, dx.get(), dy.get(), ctx.param<double>("strength"), &ctx));
  });
}

}  // namespace orogen
