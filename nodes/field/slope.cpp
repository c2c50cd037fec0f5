#include "nodes/field/slope.h"

#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/field/surface_derivatives.h"

namespace orogen {

std::shared_ptr<Heightfield> slope_field(const Heightfield& z, const ExecContext* ctx) {
  auto out = std::make_shared<Heightfield>(z.domain);
  for_each_row(ctx, z.height(), [&](int j) {
    for (int i = 0; i < z.width(); ++i) {
      double p, q;
      gradient_at(z, i, j, p, q);
      out->at(i, j) = static_cast<float>(slope_degrees(p, q));
    }
  });
  return out;
}

OROGEN_NODE(Slope) {
  b.reach_local(0.0, 1);  // central differences
  b.category("field").description(
      "Steepness in degrees (0 flat, 90 vertical): atan |grad z|, with the gradient from central differences "
      "in world units (one-sided on the border), so the same terrain gives the same slopes at any resolution.");
  b.input("in", PortType::Heightfield).description("Heights, metres");
  b.output("out", PortType::Heightfield).description("Slope angle, degrees in [0, 90)").kind(OutputKind::Scalar);
  b.execute([](ExecContext& ctx) { ctx.set_output("out", slope_field(*ctx.require<Heightfield>("in"), &ctx)); });
}

}  // namespace orogen
