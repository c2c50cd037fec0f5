#pragma once
// A color map from layer weights: at each sample the sum over layers of weight x the layer's color, times
// an optional shade.
#include <memory>
#include <string>
#include <vector>

#include <glm/vec4.hpp>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/image.h"

namespace orogen::texture {

struct NamedColor {
  std::string name;  // a channel name of the weight image
  glm::vec4 color;   // linear RGBA
};

struct ColorByLayersParams {
  std::vector<NamedColor> colors;  // when several name one layer, the last wins
  double shade_strength = 1.0;     // unitless 0..1: how much of the shade applies (0: none)
};

// The color of each channel of the weight image: the last entry of `named` with the channel's name, else
// the categorical color of the channel index.
std::vector<glm::vec4> layer_colors(const std::vector<std::string>& channel_names, int channels,
                                    const std::vector<NamedColor>& named);

// Linear RGBA (alpha 1) on the weights' domain: rgb = s x sum_c w_c color_c, with non-finite weights counted
// as 0 and s = 1 - strength + strength x clamp(shade, 0, 1) (a non-finite shade counts as 1; s = 1 without
// a shade). The weights are not normalized. The shade must lie on the weights' grid (require_same_grid: throws
// std::invalid_argument otherwise); the node brings it there with secondary_input.
std::shared_ptr<Image> color_by_layers(const Image& weights, const Heightfield* shade, const ColorByLayersParams& p,
                                       const ExecContext* ctx = nullptr);

}  // namespace orogen::texture
