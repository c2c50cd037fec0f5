#pragma once
// Surface normals as a 3-channel Image (X, Y, Z): unit vectors (-p, -q, 1) / |(-p, -q, 1)| with the
// gradient in world units (surface_derivatives.h), z up, x east, y north. A height scale exaggerates
// relief (normals of height_scale * z). The unsigned encoding stores n * 0.5 + 0.5, as normal-map
// textures do.
#include <memory>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/image.h"

namespace orogen {

std::shared_ptr<Image> normal_map(const Heightfield& z, double height_scale = 1.0, bool unsigned_encoding = false,
                                  const ExecContext* ctx = nullptr);

}  // namespace orogen
