#include "nodes/field/curvature.h"

#include <cmath>

#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"

namespace orogen {

double curvature_value(const SurfaceDerivatives& d, CurvatureKind kind) {
  const double p = d.p, q = d.q;
  const double g2 = p * p + q * q;
  if (kind == CurvatureKind::Mean)
    return -((1 + q * q) * d.r - 2 * p * q * d.s + (1 + p * p) * d.t) / (2.0 * std::pow(1.0 + g2, 1.5));
  if (g2 == 0.0) return 0.0;
  if (kind == CurvatureKind::Profile)
    return -(p * p * d.r + 2 * p * q * d.s + q * q * d.t) / (g2 * std::pow(1.0 + g2, 1.5));
  const double contour = -(q * q * d.r - 2 * p * q * d.s + p * p * d.t);
  if (kind == CurvatureKind::Plan) return contour / std::pow(g2, 1.5);
  return contour / (g2 * std::sqrt(1.0 + g2));
}

std::shared_ptr<Heightfield> curvature_field(const Heightfield& z, CurvatureKind kind, const ExecContext* ctx) {
  auto out = std::make_shared<Heightfield>(z.domain);
  for_each_row(ctx, z.height(), [&](int j) {
    for (int i = 0; i < z.width(); ++i)
      out->at(i, j) = static_cast<float>(curvature_value(derivatives_at(z, i, j), kind));
  });
  return out;
}

OROGEN_NODE(Curvature) {
  b.reach_local(0.0, 1);  // 3 x 3 stencil
  b.category("field").description(
      "Surface curvature in 1/m, positive on convex forms (summits, ridges, spurs) and negative on concave ones "
      "(valleys, hollows). profile: along the slope line (flow acceleration); plan: of the contour line "
      "(flow convergence, large near summits); tangential: plan curvature times the sine of the slope; "
      "mean: average of the principal curvatures. A sphere cap of radius R gives 1/R (plan: 1/rho).");
  b.input("in", PortType::Heightfield).description("Heights, metres");
  b.output("out", PortType::Heightfield).description("Curvature, 1/m").kind(OutputKind::Signed);
  b.param_enum("type", {"profile", "plan", "tangential", "mean"}, "profile").description("Which curvature");
  b.execute([](ExecContext& ctx) {
    const auto z = ctx.require<Heightfield>("in");
    ctx.set_output("out", curvature_field(*z, static_cast<CurvatureKind>(ctx.enum_index("type")), &ctx));
  });
}

}  // namespace orogen
