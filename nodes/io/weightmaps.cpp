#include "nodes/io/weightmaps.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <set>
#include <stdexcept>

namespace orogen {

void require_valid_weight(float weight, int layer, std::size_t sample) {
  if (!std::isfinite(weight) || weight < 0.0f)
    throw std::invalid_argument("weight of layer " + std::to_string(layer) + " at sample " + std::to_string(sample) +
                                " is " + std::to_string(weight) + "; weights must be finite and >= 0");
}

std::vector<Image> weightmap_layers(const Image& weights) {
  const int n = weights.channels;
  std::vector<Image> layers;
  layers.reserve(static_cast<std::size_t>(std::max(n, 0)));
  for (int c = 0; c < n; ++c) layers.emplace_back(weights.domain, 1);
  const std::size_t samples = weights.domain.sample_count();
  std::vector<int> codes(static_cast<std::size_t>(n));
  std::vector<double> remainders(static_cast<std::size_t>(n));
  std::vector<int> order(static_cast<std::size_t>(n));
  for (std::size_t s = 0; s < samples; ++s) {
    const float* w = weights.data.data() + s * static_cast<std::size_t>(n);
    double sum = 0.0;
    for (int c = 0; c < n; ++c) {
      require_valid_weight(w[c], c, s);
      sum += w[c];
    }
    if (!(sum > 0.0)) continue;  // no layer here: every map stays 0
    // Largest remainder: floor every share of 255, then give the codes still missing to the largest remainders
    // (ties to the lower layer), so the codes sum to 255 and each is within one of its exact share.
    int given = 0;
    for (int c = 0; c < n; ++c) {
      const double exact = 255.0 * w[c] / sum;
      codes[c] = static_cast<int>(std::floor(exact));
      remainders[c] = exact - codes[c];
      given += codes[c];
    }
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return remainders[a] > remainders[b]; });
    for (int k = 0; given < 255 && k < n; ++k, ++given) ++codes[order[k]];
    for (int c = 0; c < n; ++c) layers[c].data[s] = static_cast<float>(codes[c]) / 255.0f;
  }
  return layers;
}

std::vector<std::string> weightmap_layer_names(const Image& weights) {
  std::vector<std::string> names;
  std::set<std::string> taken;
  for (int c = 0; c < weights.channels; ++c) {
    std::string name = c < static_cast<int>(weights.channel_names.size()) ? weights.channel_names[c] : "";
    for (char& ch : name)
      if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-' && ch != '_') ch = '_';
    if (name.empty()) name = "layer" + std::to_string(c);
    std::string unique = name;
    for (int k = 2; taken.count(unique); ++k) unique = name + "_" + std::to_string(k);
    taken.insert(unique);
    names.push_back(unique);
  }
  return names;
}

}  // namespace orogen
