// ColorByLayers: a colour map from splat weights and per-layer colours.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/categorical_palette.h"
#include "nodes/common/hex_color.h"
#include "nodes/common/match_domain.h"

namespace orogen::texture {
namespace {


struct NamedColor {
  std::string name;
  glm::vec4 color;
};

// "name #rrggbb" entries separated by newlines or commas.
std::vector<NamedColor> parse_colors(const std::string& text) {
  std::vector<NamedColor> out;
  std::string norm = text;
  for (char& c : norm)
    if (c == ',') c = '\n';
  std::istringstream in(norm);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string name, hex, extra;
    if (!(ls >> name)) continue;
    if (!(ls >> hex) || (ls >> extra)) throw NodeError("colors: expected 'name #rrggbb', got '" + line + "'");
    const auto rgb = parse_hex_color(hex);
    if (!rgb) throw NodeError("colors: '" + hex + "' is not #rrggbb");
    out.push_back({name, hex_to_linear(*rgb)});
  }
  return out;
}

}  // namespace

OROGEN_NODE(ColorByLayers) {
  b.reach_pointwise();
  b.category("texture").description(
      "Color map from layer weights (SplatWeights.out or any weight image): sum over layers of weight x the "
      "layer's color (matched by channel name; layers without a color get a categorical one), times an "
      "optional shade (ambient occlusion, hillshade). Linear RGBA. Height bands as in H. Zaiz (2022), "
      "Procedural Generation of 3D Game Worlds, are SplatWeights layers with hard height rules.");
  b.input("in", PortType::Image).description("Layer weights, one channel per layer");
  b.input("shade", PortType::Heightfield).optional().description("Multiplier in 0..1 (AmbientOcclusion.out, Hillshade.out)");
  b.output("out", PortType::Image).description("Linear RGBA colors");
  b.param_string("colors", "grass #5b7f32\ndirt #7a6248\nrock #80786f\nsnow #f4f6f8\nsand #d9c48f\nwater #2f5f8a")
      .description("Layer colors, 'name #rrggbb' (sRGB) separated by newlines or commas");
  b.param_float("shade_strength", 1.0).range(0.0, 1.0).description("How much of the shade applies, 0..1 (0: none)");
  b.execute([](ExecContext& ctx) {
    const auto w = ctx.require<Image>("in");
    const auto shade = secondary_input<Heightfield>(ctx, "shade", w->domain);
    const auto named = parse_colors(ctx.param<std::string>("colors"));
    std::vector<glm::vec4> colors;
    for (int c = 0; c < w->channels; ++c) {
      glm::vec4 col = categorical_linear(c);
      if (static_cast<std::size_t>(c) < w->channel_names.size())
        for (const auto& nc : named)
          if (nc.name == w->channel_names[static_cast<std::size_t>(c)]) col = nc.color;
      colors.push_back(col);
    }
    const double strength = ctx.param<double>("shade_strength");
    auto out = std::make_shared<Image>(w->domain, 4);
    out->channel_names = {"R", "G", "B", "A"};
    for_each_row(&ctx, w->height(), [&](int j) {
      for (int i = 0; i < w->width(); ++i) {
        const float* px = w->pixel(i, j);
        glm::vec4 sum(0.0f);
        for (int c = 0; c < w->channels; ++c) sum += (std::isfinite(px[c]) ? px[c] : 0.0f) * colors[static_cast<std::size_t>(c)];
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
    ctx.set_output("out", out);
  });
}

}  // namespace orogen::texture
