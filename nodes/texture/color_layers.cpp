// ColorByLayers: a color map from splat weights and per-layer colors.
#include "nodes/texture/color_layers.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "graph/registry.h"
#include "graph/table_json.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/categorical_palette.h"
#include "nodes/common/match_domain.h"

namespace orogen::texture {
namespace {

TableSchema layer_color_schema() {
  TableSchema s;
  s.add("name", ColumnType::Text).describe("Layer name, matched against the weight image's channel names");
  s.add("color", ColumnType::Color).describe("The layer's color, sRGB #rrggbb");
  return s;
}

// The table's rows as linear colors; a name given twice takes its last color.
std::vector<NamedColor> named_colors_from_table(const TableValue& table) {
  std::vector<NamedColor> out;
  for (const auto& row : table.rows) out.push_back({std::get<std::string>(row[0]), std::get<Srgb8>(row[1]).linear()});
  return out;
}

}  // namespace

std::vector<glm::vec4> layer_colors(const std::vector<std::string>& channel_names, int channels,
                                    const std::vector<NamedColor>& named) {
  std::vector<glm::vec4> colors;
  for (int c = 0; c < channels; ++c) {
    glm::vec4 col = categorical_linear(c);
    if (static_cast<std::size_t>(c) < channel_names.size())
      for (const auto& nc : named)
        if (nc.name == channel_names[static_cast<std::size_t>(c)]) col = nc.color;
    colors.push_back(col);
  }
  return colors;
}

std::shared_ptr<Image> color_by_layers(const Image& w, const Heightfield* shade, const ColorByLayersParams& p,
                                       const ExecContext* ctx) {
  if (shade) require_same_grid(shade->domain, w.domain, "shade");  // the node resamples it (secondary_input)
  const std::vector<glm::vec4> colors = layer_colors(w.channel_names, w.channels, p.colors);
  const double strength = p.shade_strength;
  auto out = std::make_shared<Image>(w.domain, 4);
  out->channel_names = {"R", "G", "B", "A"};
  out->color = true;
  for_each_row(ctx, w.height(), [&](int j) {
    for (int i = 0; i < w.width(); ++i) {
      const float* px = w.pixel(i, j);
      glm::vec4 sum(0.0f);
      for (int c = 0; c < w.channels; ++c)
        sum += (std::isfinite(px[c]) ? px[c] : 0.0f) * colors[static_cast<std::size_t>(c)];
      float s = 1.0f;
      if (shade) {
        const float v = shade->at(i, j);
        s = static_cast<float>(1.0 - strength + strength * (std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 1.0f));
      }
      float* o = out->pixel(i, j);
      o[0] = sum.r * s;
      o[1] = sum.g * s;
      o[2] = sum.b * s;
      o[3] = 1.0f;
    }
  });
  return out;
}

OROGEN_NODE(ColorByLayers) {
  b.reach_pointwise();
  b.category("texture").description(
      "Color map from layer weights (SplatWeights.out or any weight image): sum over layers of weight x the "
      "layer's color (matched by channel name; layers without a color get a categorical one), times an "
      "optional shade (ambient occlusion, hillshade). Linear RGBA. Height bands as in H. Zaiz (2022), "
      "Procedural Generation of 3D Game Worlds, are SplatWeights layers with hard height rules.");
  b.input("in", PortType::Image).description("Layer weights, one channel per layer");
  b.input("shade", PortType::Heightfield)
      .optional()
      .description("Multiplier in 0..1 (AmbientOcclusion.out, Hillshade.out)");
  b.output("out", PortType::Image).description("Linear RGBA colors");
  b.param_table("colors", layer_color_schema(),
                table_from_json_text(R"([{"name": "grass", "color": "#5b7f32"}, {"name": "dirt", "color": "#7a6248"},
                                         {"name": "rock", "color": "#80786f"}, {"name": "snow", "color": "#f4f6f8"},
                                         {"name": "sand", "color": "#d9c48f"}, {"name": "water", "color": "#2f5f8a"}])",
                                     layer_color_schema()))
      .description("Layer colors: one row per layer, its name and sRGB color");
  b.param_float("shade_strength", 1.0)
      .unit(Unit::Unitless)
      .range(0.0, 1.0)
      .description("How much of the shade applies, 0..1 (0: none)");
  b.execute([](ExecContext& ctx) {
    const auto w = ctx.require<Image>("in");
    const auto shade = secondary_input<Heightfield>(ctx, "shade", w->domain);
    ColorByLayersParams p;
    p.colors = named_colors_from_table(ctx.param<TableValue>("colors"));
    p.shade_strength = ctx.param<double>("shade_strength");
    ctx.set_output("out", color_by_layers(*w, shade.get(), p, &ctx));
  });
}

}  // namespace orogen::texture
