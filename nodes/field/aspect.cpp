#include "nodes/field/aspect.h"

#include <cmath>
#include <numbers>

#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/field/surface_derivatives.h"

namespace orogen {

double aspect_value(double p, double q, AspectOutput output, double flat) {
  const double g = std::hypot(p, q);
  if (g == 0.0) return output == AspectOutput::Degrees ? flat : 0.0;
  // Downhill direction (-p, -q): east component -p, north component -q.
  switch (output) {
    case AspectOutput::Northness:
      return -q / g;
    case AspectOutput::Eastness:
      return -p / g;
    case AspectOutput::Degrees:
      break;
  }
  double deg = std::atan2(-p, -q) * (180.0 / std::numbers::pi);
  if (deg < 0.0) deg += 360.0;
  return deg >= 360.0 ? 0.0 : deg;
}

std::shared_ptr<Heightfield> aspect_field(const Heightfield& z, AspectOutput output, double flat,
                                          const ExecContext* ctx) {
  auto out = std::make_shared<Heightfield>(z.domain);
  for_each_row(ctx, z.height(), [&](int j) {
    for (int i = 0; i < z.width(); ++i) {
      double p, q;
      gradient_at(z, i, j, p, q);
      out->at(i, j) = static_cast<float>(aspect_value(p, q, output, flat));
    }
  });
  return out;
}

OROGEN_NODE(Aspect) {
  b.reach_local(0.0, 1);  // central differences
  b.category("field").description(
      "Direction a slope faces (downhill), clockwise from north: north = world +y (0 deg), east = +x (90 deg), "
      "south 180, west 270. 'northness' (cos) and 'eastness' (sin) avoid the wrap at north and are 0 on flats; "
      "useful for sun-facing vegetation rules (the 'skew' of J. Hammes (2001), \"Modeling of ecosystems as a "
      "data source for real-time terrain rendering\", Digital Earth Moving, LNCS 2181).");
  b.input("in", PortType::Heightfield).description("Heights, metres");
  b.output("out", PortType::Heightfield)
      .description("Degrees in [0, 360), or northness / eastness in [-1, 1]")
      .kind(OutputKind::Scalar);
  b.param_enum("output", {"degrees", "northness", "eastness"}, "degrees").description("What to output");
  b.param_float("flat_value", 0.0)
      .range(-360.0, 360.0)
      .unit(Unit::Degree)
      .description("degrees output on exactly flat samples");
  b.execute([](ExecContext& ctx) {
    const auto z = ctx.require<Heightfield>("in");
    ctx.set_output("out", aspect_field(*z, static_cast<AspectOutput>(ctx.enum_index("output")),
                                       ctx.param<double>("flat_value"), &ctx));
  });
}

}  // namespace orogen
