#include "nodes/io/control_map.h"

#include "nodes/io/weightmaps.h"

#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>

namespace orogen {

std::vector<std::uint32_t> control_words(const Image& weights, const ControlMapFlags& flags) {
  const int n = weights.channels;
  if (n > kControlMapMaxLayers)
    throw std::invalid_argument(std::to_string(n) + " layers; a control map holds texture ids 0.." +
                                std::to_string(kControlMapMaxLayers - 1));
  const std::size_t samples = weights.domain.sample_count();
  std::vector<std::uint32_t> words(samples);
  for (std::size_t s = 0; s < samples; ++s) {
    const float* w = weights.data.data() + s * static_cast<std::size_t>(n);
    int base = -1, overlay = -1;
    for (int c = 0; c < n; ++c) {
      require_valid_weight(w[c], c, s);
      if (!(w[c] > 0.0f)) continue;
      if (base < 0 || w[c] > w[base]) {
        overlay = base;
        base = c;
      } else if (overlay < 0 || w[c] > w[overlay]) {
        overlay = c;
      }
    }
    unsigned blend = 0;
    if (base < 0) {
      base = 0;
      overlay = 0;
    } else if (overlay < 0) {
      overlay = base;
    } else {
      const double share = static_cast<double>(w[overlay]) / (static_cast<double>(w[base]) + w[overlay]);
      blend = static_cast<unsigned>(std::lround(255.0 * share));
    }
    words[s] = encode_control(static_cast<unsigned>(base), static_cast<unsigned>(overlay), blend, false,
                              flags.navigation, flags.autoshader);
  }
  return words;
}

Image control_map_image(const Domain& domain, const std::vector<std::uint32_t>& words) {
  Image image(domain, 1);
  image.channel_names = {"R"};
  for (std::size_t s = 0; s < words.size(); ++s) image.data[s] = std::bit_cast<float>(words[s]);
  return image;
}

}  // namespace orogen
