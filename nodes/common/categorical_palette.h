#pragma once
// One color per class id, shared by the nodes that color labels (KMeansClusters, ColorByLayers) and the
// editor's categorical preview, so an id looks the same in a node's image and in the preview.
//
// Ids 0..11: Tableau 10 followed by two more distinct colors; ids from 12 on: hues spaced by the golden ratio
// (saturation 0.6, value 0.85), so every id differs from its neighbours; negative ids ("no class", e.g.
// Biomes' -1): neutral gray. Header-only so the editor uses it without linking the nodes.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "nodes/common/color_space.h"
#include "nodes/common/hex_color.h"

namespace orogen {

inline constexpr std::array<std::uint32_t, 12> kCategoricalPalette{0x4e79a7, 0xf28e2b, 0xe15759, 0x76b7b2,
                                                                   0x59a14f, 0xedc948, 0xb07aa1, 0xff9da7,
                                                                   0x9c755f, 0xbab0ac, 0x1b3a6b, 0x8cd17d};

// The color of a negative id, sRGB.
inline constexpr float kNoClassGray = 0.5f;

// sRGB color of class `id`, channels in [0, 1].
inline glm::vec3 categorical_srgb(long id) {
  if (id < 0) return glm::vec3(kNoClassGray);
  if (id < static_cast<long>(kCategoricalPalette.size()))
    return hex_to_srgb(kCategoricalPalette[static_cast<std::size_t>(id)]);
  const double h = std::fmod(0.618033988749895 * static_cast<double>(id), 1.0) * 6.0;
  const int sector = static_cast<int>(h) % 6;
  const float f = static_cast<float>(h - std::floor(h)), v = 0.85f, s = 0.6f;
  const float p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  const float rgb[6][3] = {{v, t, p}, {q, v, p}, {p, v, t}, {p, q, v}, {t, p, v}, {v, p, q}};
  return {rgb[sector][0], rgb[sector][1], rgb[sector][2]};
}

// Linear RGBA (alpha 1) of class `id`: categorical_srgb through srgb_to_linear in float.
inline glm::vec4 categorical_linear(long id) {
  const glm::vec3 c = categorical_srgb(id);
  return {srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b), 1.0f};
}

}  // namespace orogen
