#pragma once
// CPU side of the 3D viewport: a heightfield as an indexed triangle grid with normals and colours (the
// terrain colour map by height, or a draped image sampled at each vertex's world position).
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "editor/model/preview_image.h"
#include "graph/heightfield.h"
#include "graph/image.h"

namespace orogen::editor {

struct TerrainMesh {
  std::vector<glm::vec3> positions;  // world metres (z = height * vertical_scale)
  std::vector<glm::vec3> normals;    // unit, of the scaled surface
  std::vector<glm::vec4> colors;     // sRGB in 0..1
  std::vector<std::uint32_t> indices;  // triangles
  glm::vec3 min{0.0f}, max{0.0f};      // bounds of positions
  int columns = 0, rows = 0;           // vertex grid
};

struct TerrainMeshOptions {
  int max_side = 512;              // at most this many vertices along each side (decimated by striding)
  float vertical_scale = 1.0f;     // exaggeration
  ColorMap map = ColorMap::Terrain;
  const Image* drape = nullptr;    // optional colour image, sampled by world position (nearest)
};

TerrainMesh build_terrain_mesh(const Heightfield& field, const TerrainMeshOptions& options = {});

}  // namespace orogen::editor
