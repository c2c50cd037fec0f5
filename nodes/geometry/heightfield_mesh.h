#pragma once
// Heightfield to triangle mesh: a grid triangulation in world coordinates and its decimation to a vertical
// error bound in metres.
#include <cstddef>
#include <functional>

#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/mesh.h"

namespace orogen {

// The grid mesh of a heightfield: vertex (i, j) at (x(i), y(j), height(i, j)) in world metres, z up, with
// index j * width + i. Each cell is split into two counter-clockwise triangles (seen from +z) along its
// shorter 3D diagonal, so ridges and valleys running diagonally are kept. Vertex normals are the surface
// normals of the heightfield by central differences (one-sided at the border), exact for planes. Vertex
// colours are the image bilinearly sampled at each vertex's world position (1 channel: grey, 2: grey +
// alpha, 3: RGB, 4+: RGBA), or opaque white without an image. Throws std::invalid_argument for fewer than
// 2 x 2 samples or a field too large for 32-bit mesh indices.
Mesh heightfield_grid_mesh(const Heightfield& height, const Image* colors = nullptr);

struct DecimationOptions {
  // Largest vertical distance, in metres, between any original sample and the decimated surface; 0 or
  // less: no error bound (then target_faces alone stops the decimation).
  double max_error = 0.0;
  // Stop once the mesh has at most this many faces; 0: no target (decimate as far as max_error allows).
  std::size_t target_faces = 0;
  std::function<void(double)> progress;     // optional, fraction of the vertices removed so far (approximate)
  std::function<bool()> should_stop;        // optional; true aborts early (cancellation), leaving a valid mesh
};

// Decimates a mesh made by heightfield_grid_mesh by halfedge collapses (OpenMesh Decimater): collapses are
// ordered by the error quadric (ModQuadricT), may not flip a face normal (ModNormalFlippingT), and must keep
// every original sample within max_error vertically of the surface and the mesh a heightfield over the same
// rectangle (ModHeightErrorT). Surviving vertices keep their position, normal and colour. Returns the number
// of collapses. Does nothing if neither max_error nor target_faces is set.
std::size_t decimate_heightfield_mesh(Mesh& mesh, const DecimationOptions& options);

}  // namespace orogen
