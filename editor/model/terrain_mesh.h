#pragma once
// CPU side of the 3D viewport: a heightfield as an indexed triangle grid with normals and colours (the
// terrain colour map by height, or a draped image sampled at each vertex's world position); lake water as a
// flat surface; curves (rivers) as ribbons of their width lying on the terrain.
#include <cstdint>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "editor/model/preview_image.h"
#include "graph/curves.h"
#include "graph/heightfield.h"
#include "graph/image.h"

namespace orogen::editor {

struct TerrainMesh {
  std::vector<glm::vec3> positions;    // world metres (z = height * vertical_scale)
  std::vector<glm::vec3> normals;      // unit, of the scaled surface
  std::vector<glm::vec4> colors;       // sRGB in 0..1
  std::vector<std::uint32_t> indices;  // triangles
  glm::vec3 min{0.0f}, max{0.0f};      // bounds of positions
  int columns = 0, rows = 0;           // vertex grid
};

struct TerrainMeshOptions {
  int max_side = 512;           // at most this many vertices along each side (decimated by striding)
  float vertical_scale = 1.0f;  // exaggeration
  ColorMap map = ColorMap::Terrain;
  const Image* drape = nullptr;           // optional colour image, sampled by world position (nearest)
  std::optional<ValueRange> color_range;  // mapped to the colour map's 0..1; default: the field's range
};

TerrainMesh build_terrain_mesh(const Heightfield& field, const TerrainMeshOptions& options = {});

// The water of lakes: where `depth` (m, on the terrain's lattice or resampled by world position) is > 0, a
// surface at terrain + depth. Cells with a wet corner are drawn; their dry corners take the level of their
// wet neighbours, so the surface runs flat into the shore and the terrain's depth test cuts the shoreline.
// Translucent blue, alpha growing with depth. Empty when nothing is wet. Same striding as the terrain.
TerrainMesh build_water_mesh(const Heightfield& terrain, const Heightfield& depth,
                             const TerrainMeshOptions& options = {});

struct CurveRibbonOptions {
  float min_width = 0.0f;  // metres: narrower curves are drawn this wide, so they stay visible
  float lift = 0.0f;       // metres above the higher of the curve and the terrain
  float vertical_scale = 1.0f;
};
// Each curve as a ribbon of its per-vertex width (metres), centred on the polyline, perpendicular to it in
// the horizontal plane (mitred at joints), lying at the curve's height or on `terrain` where that is higher.
// Coloured by width (light to deep blue).
TerrainMesh build_curve_ribbons(const Curves& curves, const Heightfield* terrain,
                                const CurveRibbonOptions& options = {});

}  // namespace orogen::editor
