#pragma once
// CPU side of the 2D preview: turns node outputs into RGBA8 pixels. Heightfields through a colour map
// (grey, terrain, viridis) optionally multiplied by a hillshade; images from linear floats to sRGB.
// Pixel row r shows the samples of row (height - 1 - r), so world +y points up on screen, as in the 3D
// view seen from above.
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

#include "graph/heightfield.h"
#include "graph/image.h"

namespace orogen::editor {

enum class ColorMap { Grey, Terrain, Viridis };
inline constexpr const char* kColorMapNames[] = {"grey", "terrain", "viridis"};

// Linear interpolation through the map's stops; t is clamped to [0, 1]. sRGB-encoded components in 0..1.
glm::vec3 colormap(ColorMap map, double t);

struct ValueRange {
  float lo = 0.0f, hi = 1.0f;
};
// Range of the finite values; {0, 1} if there are none; hi > lo always (flat fields get a unit span).
ValueRange value_range(const Heightfield& field);

// Lambertian shading in [0, 1] from normals computed with world-unit central differences. Light from
// `azimuth_deg` (clockwise from +y, "north"), `altitude_deg` above the horizon; GIS default 315 / 45.
std::vector<float> hillshade(const Heightfield& field, double azimuth_deg = 315.0, double altitude_deg = 45.0,
                             double z_factor = 1.0);

struct PreviewPixels {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // row-major, top row first
};

struct HeightfieldStyle {
  ColorMap map = ColorMap::Terrain;
  bool hillshade = true;
  std::optional<ValueRange> range;  // default: the field's own range
};

PreviewPixels render_heightfield(const Heightfield& field, const HeightfieldStyle& style);
// 1 channel: grey; 2: grey + alpha; 3: RGB; 4+: RGBA of the first four. Linear values are sRGB-encoded.
PreviewPixels render_image(const Image& image);

}  // namespace orogen::editor
