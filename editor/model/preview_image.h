#pragma once
// CPU side of the 2D preview: turns node outputs into RGBA8 pixels. Heightfields through a colour map
// (gray, terrain, viridis, diverging, water) optionally multiplied by a hillshade, chosen from the output's
// kind (style_for); images from linear floats to sRGB.
// Pixel row r shows the samples of row (height - 1 - r), so world +y points up on screen, as in the 3D
// view seen from above.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "graph/curves.h"
#include "graph/graph.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/node_type.h"
#include "graph/points.h"
#include "graph/port_value.h"

namespace orogen::editor {

// Categorical: ids (cluster, biome, layer numbers) each in its own colour, by the rounded value rather than
// its position in the range, from the palette the nodes color ids with (nodes/common/categorical_palette.h).
enum class ColorMap { Gray, Terrain, Viridis, Diverging, Water, Categorical };
inline constexpr const char* kColorMapNames[] = {"gray", "terrain", "viridis", "diverging", "water", "categorical"};
inline constexpr int kColorMapCount = 6;

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
  bool symmetric = false;           // without `range`: [-m, m] with m the largest |value| (0 in the middle)
};

// The range the style maps to [0, 1] for this field.
ValueRange style_range(const Heightfield& field, const HeightfieldStyle& style);

// The default look of each kind: heights in terrain tints with hillshade over their own range; masks in
// gray over exactly 0..1; signed fields diverging around 0; scalars in viridis; water depth in blues from 0.
HeightfieldStyle style_for(OutputKind kind);

// What heightfield output `port` of node `node` holds. A declared kind wins; otherwise a port named like a
// mask ("mask", "..._mask") is a mask, an operator passes on the kind of its primary heightfield input (`in`,
// else `a`, else the first connected one), and anything else is a height.
OutputKind resolve_output_kind(const Graph& graph, const std::string& node, const std::string& port);

PreviewPixels render_heightfield(const Heightfield& field, const HeightfieldStyle& style);
// Water depth (m) over its terrain: the terrain in its own style, and where depth > 0 the water, pale and
// translucent in the shallows, deep blue and nearly opaque at the deepest point. `depth` is sampled at the
// terrain's samples by world position.
PreviewPixels render_water_over_terrain(const Heightfield& terrain, const Heightfield& depth);
// 1 channel: grey; 2: grey + alpha; 3: RGB; 4+: RGBA of the first four. Linear values are sRGB-encoded.
PreviewPixels render_image(const Image& image);
// One channel of an image as a field (a month of a climate image, a splat layer), to draw with a colour map.
Heightfield image_channel(const Image& image, int channel);

// Small pictures of point sets and curves (node thumbnails): the world rectangle `domain` fitted into at
// most max_side pixels along its longer side (aspect kept, world +y up), on a dark background. Points as
// dots (2 x 2 pixels while they are sparse) in their class's marker colour; curves as lines as wide as the
// curve (at least a pixel), pale blue for narrow ones to deep blue for the widest. Anything outside the
// rectangle is clipped.
PreviewPixels render_points(const Points& points, const Domain& domain, int max_side = 128);
PreviewPixels render_curves(const Curves& curves, const Domain& domain, int max_side = 128);

// The line under the 2D preview saying what is shown: a raster (height field, image) by its samples and
// spacing; a polygon map, which is vector cells and not a raster, by its cells and extent; points, curves and
// scenes by their counts; with the terrain they are drawn over (`backdrop`) when there is one. Lengths in
// metres as typed in a graph (4096 m, not 4.1e+03 m).
std::string describe_preview_value(const PortValue& value, const Heightfield* backdrop = nullptr);

}  // namespace orogen::editor
