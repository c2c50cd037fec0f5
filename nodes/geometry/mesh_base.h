#pragma once
// Closing an open surface mesh (a terrain) into a solid for 3D printing: a skirt and a flat base.
#include "graph/mesh.h"

namespace orogen {

// A copy of `mesh` closed into a solid: every boundary loop gets a vertical wall ("skirt") from its vertices
// down to the plane z = (lowest vertex) - depth, and a flat bottom (a fan from the loop's centroid, so a
// footprint that is star-shaped from its centroid, like a terrain's rectangle, gives non-overlapping bottom
// triangles). Orientation follows the surface's: a terrain facing +z gives outward normals everywhere.
// Wall and bottom vertices copy the color of the border vertex above them; their normals point horizontally
// out (walls) or down (bottom centre). A mesh without boundary is returned unchanged. depth must be > 0.
Mesh mesh_with_base(const Mesh& mesh, double depth);

}  // namespace orogen
