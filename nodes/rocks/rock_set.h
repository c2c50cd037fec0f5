#pragma once
// A set of hull-rock variants laid out in a row, for scattering: one mesh holding them all and a point at
// the center of each.
#include "graph/exec_context.h"
#include "graph/mesh.h"
#include "graph/points.h"
#include "nodes/rocks/hull_rock.h"

namespace orogen::rocks {

struct RockSetParams {
  HullRockOptions rock;    // the shared options; each variant gets variant = its index
  int count = 8;           // number of variants, 1..1000
  double variation = 0.3;  // unitless 0..0.95: each radius is multiplied by a factor in 1 +- variation
  double spacing = 0.5;    // m: gap between neighboring variants' bounding half-widths
  TriMesh::Color color{0.35f, 0.33f, 0.3f, 1.0f};  // vertex color, linear RGBA
};

// Appends the variants to `mesh` along +x (variant 0 centered on the origin; each occupies a half-width of
// max radius + 3 sigma + displacement on either side) and to `placements` a point per variant at its
// center, class id = index, scale = its radii (m). Face normals are left to the caller. Throws
// std::invalid_argument "rock K: <reason>" when variant K has no hull.
void append_rock_set(TriMesh& mesh, Points& placements, const RockSetParams& p, const ExecContext* ctx = nullptr);

}  // namespace orogen::rocks
