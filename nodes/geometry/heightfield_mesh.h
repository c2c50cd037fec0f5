#pragma once
// Heightfield to triangle mesh: the full grid triangulation, or a TIN within a vertical error bound in metres.
#include <cstddef>
#include <functional>

#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/mesh.h"
#include "nodes/geometry/terrain_tin.h"

namespace orogen {

// The grid mesh of a heightfield: vertex (i, j) at (x(i), y(j), height(i, j)) in world metres, z up, with
// index j * width + i. Each cell is split into two counter-clockwise triangles (seen from +z) along its
// shorter 3D diagonal, so ridges and valleys running diagonally are kept. Vertex normals are the surface
// normals of the heightfield by central differences (one-sided at the border), exact for planes. Vertex
// colors are the image bilinearly sampled at each vertex's world position (1 channel: gray, 2: gray +
// alpha, 3: RGB, 4+: RGBA), or opaque white without an image. Throws std::invalid_argument for fewer than
// 2 x 2 samples or a field too large for 32-bit mesh indices.
Mesh heightfield_grid_mesh(const Heightfield& height, const Image* colors = nullptr);

// The TIN of the heightfield within options' bound (see terrain_tin.h) as a mesh: its vertices are samples,
// with the positions, normals and colors heightfield_grid_mesh gives them. With neither max_error nor
// target_faces set, the grid mesh. Throws std::invalid_argument like heightfield_grid_mesh.
Mesh heightfield_mesh(const Heightfield& height, const Image* colors, const TinOptions& options);

}  // namespace orogen
