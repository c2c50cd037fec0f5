#pragma once
// Tree meshes: generalized cylinders (Bloomenthal 1985, Modeling the mighty maple; Prusinkiewicz et al.
// 1988/1990) swept along the branches of a turtle skeleton, plus leaves.
#include <cstddef>
#include <functional>

#include "graph/curves.h"
#include "graph/mesh.h"
#include "graph/points.h"

namespace orogen::plants {

enum class LeafShape { None, Quad, Rock };

struct TreeMeshOptions {
  int sides = 8;                       // k, samples around each branch (3..64)
  std::size_t max_triangles = 200000;  // budget for branches and leaves together
  LeafShape leaf_shape = LeafShape::Quad;
  int rock_points = 8;     // hull points per rock leaf
  std::uint64_t seed = 0;  // rock leaves' shapes
  std::function<bool()> should_stop;
};

struct TreeMeshStats {
  int sides = 0;  // sides actually used (reduced to meet the budget)
  std::size_t dropped_branches = 0;
  std::size_t dropped_leaves = 0;
  std::size_t branch_triangles = 0, leaf_triangles = 0;
};

// Each branch (curve with >= 2 distinct points) becomes a closed tube: a ring of `sides` vertices at every
// point, in a rotation-minimising (parallel transport) frame, radius = width / 2, colored by the curve's
// "r", "g", "b" attributes (linear; gray when absent), capped by a fan at both ends. Children start on
// their parent's axis, so their base caps sit inside the parent and the joint shows no gap; the widest child
// starting at its parent's end point starts with the parent's end radius (the axis tapers through the joint). Faces
// wind counter-clockwise seen from outside. Texture coordinates: u around the branch (0..1), v along it in metres of
// arc length (stored in the mesh's vertex texcoords; the seam vertex is not duplicated, so the tube stays closed and u
// wraps from (k-1)/k back to 0). Leaves (optional): a diamond quad in the leaf's heading-left plane facing its up axis,
// or a small closed convex hull. Over the budget, first the sides shrink (to 3), then leaves and the thinnest twigs
// (curves without children, and their leaves) are dropped.
Mesh tree_mesh(const Curves& skeleton, const Points* leaves, const TreeMeshOptions& options,
               TreeMeshStats* stats = nullptr);

}  // namespace orogen::plants
