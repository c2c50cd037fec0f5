#include "nodes/field/color_ramp.h"

#include <cmath>

#include "graph/registry.h"
#include "nodes/field/field_range.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/color_space.h"

namespace orogen {
namespace {

GradientValue::Stop stop_at_height(double h, double r, double g, double b) {
  return {(h - kTerrainGradientMin) / (kTerrainGradientMax - kTerrainGradientMin),
          glm::vec4(static_cast<float>(srgb_to_linear(r)), static_cast<float>(srgb_to_linear(g)),
                    static_cast<float>(srgb_to_linear(b)), 1.0f)};
}

}  // namespace

GradientValue terrain_height_gradient() {
  return {{
      stop_at_height(-100.0, 0.04, 0.10, 0.30),  // deep water
      stop_at_height(-40.0, 0.07, 0.22, 0.48),
      stop_at_height(0.0, 0.20, 0.50, 0.68),  // shallow water up to the shoreline
      stop_at_height(0.0, 0.86, 0.80, 0.58),  // sand (hard edge at sea level)
      stop_at_height(12.0, 0.80, 0.74, 0.52),
      stop_at_height(30.0, 0.38, 0.60, 0.22),   // grass
      stop_at_height(250.0, 0.14, 0.36, 0.13),  // forest
      stop_at_height(450.0, 0.20, 0.33, 0.17),
      stop_at_height(520.0, 0.48, 0.43, 0.39),  // rock
      stop_at_height(760.0, 0.60, 0.58, 0.56),
      stop_at_height(820.0, 0.95, 0.96, 0.98),  // snow
      stop_at_height(900.0, 1.00, 1.00, 1.00),
  }};
}

std::shared_ptr<Image> color_ramp(const Heightfield& in, const GradientValue& gradient, double lo, double hi,
                                  const ExecContext* ctx) {
  auto out = std::make_shared<Image>(in.domain, 4);
  out->channel_names = {"R", "G", "B", "A"};
  out->color = true;
  const double inv = 1.0 / (hi - lo);
  for_each_row(ctx, in.height(), [&](int j) {
    for (int i = 0; i < in.width(); ++i) {
      const glm::vec4 c = gradient.evaluate((in.at(i, j) - lo) * inv);
      float* px = out->pixel(i, j);
      for (int k = 0; k < 4; ++k) px[k] = c[k];
    }
  });
  return out;
}

OROGEN_NODE(ColorRamp) {
  b.distribution(Distribution::Reduction);
  b.reach(
      [](const ParamView& p) { return p.get<std::string>("range") == "field" ? Reach::global() : Reach::pointwise(); },
      "point-wise; global with range = field");
  b.category("field").description(
      "Colors a field through a gradient: t = (h - input_min) / (input_max - input_min) in 0..1 picks the "
      "color (beyond the ends, the end colors). The default gradient is a hypsometric tint (E. Imhof (1982), "
      "Cartographic Relief Presentation) over -100..900 m: deep and shallow water, a sand shore at 0 m, grass, forest, "
      "rock, snow. Output: linear RGBA.");
  b.input("in", PortType::Heightfield).description("Field to color (heights in metres for the default gradient)");
  b.output("out", PortType::Image).description("Linear RGBA colors");
  b.param_gradient("gradient", terrain_height_gradient()).description("Color stops by position in 0..1 (linear RGBA)");
  b.param_enum("range", {"fixed", "field"}, "fixed")
      .description("fixed: input_min..input_max maps to 0..1; field: the field's own min..max does");
  b.param_float("input_min", kTerrainGradientMin)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Value at gradient position 0, in the input's units");
  b.param_float("input_max", kTerrainGradientMax)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Value at gradient position 1 (!= input_min), in the input's units");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    double lo = ctx.param<double>("input_min"), hi = ctx.param<double>("input_max");
    if (ctx.param<std::string>("range") == "field") {
      const ValueRange r = field_range(*in, &ctx);
      lo = r.min;
      hi = r.max > r.min ? r.max : r.min + 1.0;  // flat field: everything at the start of the gradient
    } else if (lo == hi) {
      throw NodeError("ColorRamp: input_min equals input_max");
    }
    ctx.set_output("out", color_ramp(*in, ctx.param<GradientValue>("gradient"), lo, hi, &ctx));
  });
}

}  // namespace orogen
