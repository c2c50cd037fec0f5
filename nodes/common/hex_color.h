#pragma once
// Colors typed as "#rrggbb" (sRGB, 8 bits per channel), as node parameters and the editor take them.
// Header-only so the editor uses the same parser without linking the nodes.
#include <cstdint>
#include <optional>
#include <string_view>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "nodes/common/color_space.h"

namespace orogen {

// 0xRRGGBB from exactly '#' and six hex digits (either case); nullopt for anything else (no blanks, no
// "#rgb" short form, no alpha).
inline std::optional<std::uint32_t> parse_hex_color(std::string_view text) {
  if (text.size() != 7 || text[0] != '#') return std::nullopt;
  std::uint32_t v = 0;
  for (const char c : text.substr(1)) {
    int d;
    if (c >= '0' && c <= '9')
      d = c - '0';
    else if (c >= 'a' && c <= 'f')
      d = c - 'a' + 10;
    else if (c >= 'A' && c <= 'F')
      d = c - 'A' + 10;
    else
      return std::nullopt;
    v = v << 4 | static_cast<std::uint32_t>(d);
  }
  return v;
}

// The sRGB channels of 0xRRGGBB in [0, 1].
inline glm::vec3 hex_to_srgb(std::uint32_t rgb) {
  return {static_cast<float>((rgb >> 16) & 255) / 255.0f, static_cast<float>((rgb >> 8) & 255) / 255.0f,
          static_cast<float>(rgb & 255) / 255.0f};
}

// 0xRRGGBB as linear RGBA (alpha 1), each channel through srgb_to_linear in float.
inline glm::vec4 hex_to_linear(std::uint32_t rgb) {
  const glm::vec3 s = hex_to_srgb(rgb);
  return {srgb_to_linear(s.r), srgb_to_linear(s.g), srgb_to_linear(s.b), 1.0f};
}

}  // namespace orogen
