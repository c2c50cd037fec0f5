#include "nodes/field/linear_gradient.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "graph/exec_context.h"
#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"

namespace orogen {

double linear_gradient_at(const LinearGradientParams& params, glm::dvec2 p) {
  const double a = params.angle_deg * std::numbers::pi / 180.0;
  const glm::dvec2 dir{std::cos(a), std::sin(a)};
  const double t = std::clamp(glm::dot(p - params.start, dir) / params.length, 0.0, 1.0);
  return params.from + t * (params.to - params.from);
}

void linear_gradient_row(const LinearGradientParams& params, const Domain& domain, int j, std::span<float> out) {
  for (int i = 0; i < domain.width(); ++i)
    out[static_cast<std::size_t>(i)] = static_cast<float>(linear_gradient_at(params, domain.position(i, j)));
}

Heightfield linear_gradient(const LinearGradientParams& params, const Domain& domain) {
  Heightfield out(domain);
  for (int j = 0; j < domain.height(); ++j) linear_gradient_row(params, domain, j, out.row(j));
  return out;
}

// --- node ---

OROGEN_NODE(LinearGradient) {
  b.reach_pointwise();
  b.category("field").description(
      "A linear ramp in world space: the value goes from 'from' to 'to' along the direction 'angle', across "
      "the span that begins at 'start' and is 'length' metres long. Before the span the value is 'from', after "
      "it 'to' (clamped). Resolution independent.");
  b.output("out", PortType::Heightfield).description("The ramp, metres").kind(OutputKind::Height);
  b.param_float("from", 0.0)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .unit(Unit::Metre)
      .description("Value at the start of the span and before it");
  b.param_float("to", 100.0)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .unit(Unit::Metre)
      .description("Value at the end of the span and beyond it");
  b.param_float("angle", 0.0)
      .range(-360, 360)
      .unit(Unit::Degree)
      .description(
          "Direction in which the value goes from 'from' to 'to': 0 = +x (east), 90 = +y (north), "
          "counter-clockwise");
  b.param_vec2("start", {0.0, 0.0})
      .range(-1e7, 1e7)
      .unit(Unit::Metre)
      .description("World point where the span begins; the ramp's iso-lines are perpendicular to the direction");
  b.param_float("length", 1024.0)
      .range(1e-3, 1e7)
      .soft_range(1, 10000)
      .unit(Unit::Metre)
      .description("Length of the span along the direction, metres");
  b.execute([](ExecContext& ctx) {
    LinearGradientParams p;
    p.from = ctx.param<double>("from");
    p.to = ctx.param<double>("to");
    p.angle_deg = ctx.param<double>("angle");
    p.start = ctx.param<glm::dvec2>("start");
    p.length = ctx.param<double>("length");
    auto out = std::make_shared<Heightfield>(ctx.domain());
    parallel_rows(ctx, ctx.domain().height(), [&](int j) { linear_gradient_row(p, ctx.domain(), j, out->row(j)); });
    ctx.set_output("out", std::move(out));
  });
}

}  // namespace orogen
