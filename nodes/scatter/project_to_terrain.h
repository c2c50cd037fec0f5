#pragma once
// Points set onto a terrain: z from the heights under them, rotation optionally tilted toward the normal.
#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/points.h"

namespace orogen {

struct ProjectParams {
  double offset = 0.0;  // m, added to the terrain height
  double align = 0.0;   // unitless 0..1: 0 keeps the rotation, 1 turns the up axis onto the terrain normal
};

// Each point's z becomes the bilinear height under it (clamped at the field's border) plus the offset; it is
// kept where that height is not finite. With align > 0 its rotation is premultiplied by the slerp, by align,
// from identity to the shortest rotation of +z onto the normal (-dz/dx, -dz/dy, 1) normalized, the gradient
// from central differences one sample apart in world units; where the gradient is not finite it is kept.
Points project_to_terrain(const Points& in, const Heightfield& height, const ProjectParams& p,
                          const ExecContext* ctx = nullptr);

}  // namespace orogen
