#include "terraced_canyon.h"

#include <algorithm>
#include <cmath>

namespace canyon {

double canyon_cut(double x, double y, const CanyonParams& p) {
  const double pi = 3.14159265358979323846;
  const double center = p.center_y + p.amplitude * std::sin(2.0 * pi * x / p.wavelength);
  const double t = std::min(std::abs(y - center) / (0.5 * p.width), 1.0);  // 0 on the center line, 1 at the rim
  const double s = t <= p.floor ? 0.0 : (t - p.floor) / (1.0 - p.floor);
  const double wall = s * s * (3.0 - 2.0 * s);  // smoothstep
  const double cut = p.depth * (1.0 - wall);
  if (p.terrace <= 0.0 || cut <= 0.0) return cut;
  return std::min(p.depth, p.terrace * std::ceil(cut / p.terrace));
}

orogen::HeightfieldPtr carve_canyon(const orogen::Heightfield& in, const CanyonParams& p,
                                    const orogen::ExecContext* ctx) {
  auto out = std::make_shared<orogen::Heightfield>(in.domain);
  const auto& d = in.domain;
  for (int j = 0; j < d.height(); ++j) {
    if (ctx) ctx->check_cancelled();
    for (int i = 0; i < d.width(); ++i) out->at(i, j) = static_cast<float>(in.at(i, j) - canyon_cut(d.x(i), d.y(j), p));
  }
  return out;
}

}  // namespace canyon

OROGEN_NODE(TerracedCanyon) {
  using orogen::PortType;
  using orogen::Unit;
  b.category("field").description(
      "Cuts a canyon with terraced walls into the heights along a meandering center line y = center_y + "
      "amplitude sin(2 pi x / wavelength): depth on the floor, a smoothstep wall to the rim, rounded up to whole "
      "terrace steps. A procedural profile (an example node of the Orogen SDK), not a published erosion model.");
  b.reach_pointwise();
  b.input("in", PortType::Heightfield).description("Heights, metres");
  b.output("out", PortType::Heightfield).description("Heights with the canyon cut out, metres");
  b.param_float("center_y", 0.0)
      .range(-1e7, 1e7)
      .soft_range(-5000, 5000)
      .unit(Unit::Metre)
      .description("Mean y of the center line");
  b.param_float("amplitude", 100.0)
      .range(0.0, 1e5)
      .soft_range(0, 1000)
      .unit(Unit::Metre)
      .description("How far the center line meanders to each side");
  b.param_float("wavelength", 800.0)
      .range(1.0, 1e6)
      .soft_range(100, 5000)
      .unit(Unit::Metre)
      .description("Length of one meander along x");
  b.param_float("width", 200.0)
      .range(1.0, 1e5)
      .soft_range(10, 2000)
      .unit(Unit::Metre)
      .description("Canyon width from rim to rim");
  b.param_float("depth", 60.0)
      .range(0.0, 1e4)
      .soft_range(0, 500)
      .unit(Unit::Metre)
      .description("Cut at the center line");
  b.param_float("terrace", 10.0)
      .range(0.0, 1e4)
      .soft_range(0, 100)
      .unit(Unit::Metre)
      .description("Height of one terrace step of the walls; 0 for smooth walls");
  b.param_float("floor", 0.2)
      .range(0.0, 0.95)
      .unit(Unit::Unitless)
      .description("Unitless fraction of the half width that is flat floor");
  b.execute([](orogen::ExecContext& ctx) {
    canyon::CanyonParams p;
    p.center_y = ctx.param<double>("center_y");
    p.amplitude = ctx.param<double>("amplitude");
    p.wavelength = ctx.param<double>("wavelength");
    p.width = ctx.param<double>("width");
    p.depth = ctx.param<double>("depth");
    p.terrace = ctx.param<double>("terrace");
    p.floor = ctx.param<double>("floor");
    ctx.set_output("out", canyon::carve_canyon(*ctx.require<orogen::Heightfield>("in"), p, &ctx));
  });
}
