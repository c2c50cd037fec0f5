#pragma once
// N float channels sampled on a Domain, interleaved per sample: colour maps (RGB/RGBA in 0..1, linear),
// splat weights, normal maps; `color` tells the first from data.
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "graph/domain.h"

namespace orogen {

struct Image {
  Domain domain;
  int channels = 0;
  std::vector<std::string> channel_names;  // e.g. {"R","G","B"}; empty means unnamed
  std::vector<float> data;                 // (row * width + column) * channels + channel
  // Linear color (RGB or RGBA, set by the nodes that make colors): encoded with the sRGB curve when written to
  // an 8- or 16-bit file. Every other image (splat weights, masks, ids, normals, monthly figures) is data,
  // written as its values.
  bool color = false;

  Image() = default;
  Image(const Domain& d, int channel_count, float fill = 0.0f)
      : domain(d), channels(channel_count), data(d.sample_count() * static_cast<std::size_t>(channel_count), fill) {}

  int width() const { return domain.width(); }
  int height() const { return domain.height(); }
  float* pixel(int i, int j) { return data.data() + offset(i, j); }
  const float* pixel(int i, int j) const { return data.data() + offset(i, j); }
  std::size_t offset(int i, int j) const {
    return (static_cast<std::size_t>(j) * static_cast<std::size_t>(width()) + static_cast<std::size_t>(i)) *
           static_cast<std::size_t>(channels);
  }
  std::size_t byte_size() const { return data.size() * sizeof(float) + sizeof(*this); }
};

using ImagePtr = std::shared_ptr<const Image>;

}  // namespace orogen
