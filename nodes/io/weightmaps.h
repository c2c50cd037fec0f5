#pragma once
// Splat weights as one 8-bit grayscale weightmap per layer, the form Unreal Engine's landscape paint layers
// import ("weight-blended" layers: the maps of one landscape sum to 255 at every sample).
#include <string>
#include <vector>

#include "graph/image.h"

namespace orogen {

// Throws std::invalid_argument naming the layer and sample unless the weight is finite and >= 0 (what every
// reader of splat weights, here and in control_map.h, requires).
void require_valid_weight(float weight, int layer, std::size_t sample);

// One single-channel image per channel of `weights`, holding codes / 255 of 8-bit codes that sum to exactly
// 255 at every sample: the weights are normalized by their sum and rounded by largest remainder (each code is
// within one of 255 * w / sum). A sample whose weights are all zero stays 0 in every map. Throws
// std::invalid_argument (with the layer and sample) for a negative or non-finite weight.
std::vector<Image> weightmap_layers(const Image& weights);

// File-name-safe layer names: the image's channel names (letters, digits, '-' and '_' kept, anything else
// '_'), "layer<N>" where a name is missing or empty, and a numeric suffix where two would collide.
std::vector<std::string> weightmap_layer_names(const Image& weights);

}  // namespace orogen
