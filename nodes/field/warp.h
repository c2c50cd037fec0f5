#pragma once
// Warp: resample a field at positions displaced by displacement fields (metres), so features bend and
// swirl. out(p) = in(p + strength * (dx(p), dy(p))), looked up with bicubic Catmull-Rom interpolation;
// positions beyond the field's rectangle are clamped to its edge.
#include <memory>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

// dx and dy must lie on in's domain (or be null for no displacement along that axis).
std::shared_ptr<Heightfield> warp_field(const Heightfield& in, const Heightfield* dx, const Heightfield* dy,
                                        double strength, const ExecContext* ctx = nullptr);

}  // namespace orogen
