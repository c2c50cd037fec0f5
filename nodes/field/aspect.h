#pragma once
// Aspect: the compass direction a slope faces (its downhill direction), in degrees clockwise from north,
// where north is world +y and east is world +x: a slope falling towards +y faces 0, towards +x 90,
// towards -y 180, towards -x 270. Values lie in [0, 360). Flat samples have no direction and get a
// caller-chosen value. Northness cos(aspect) and eastness sin(aspect) are the continuous alternatives
// (no wrap at north), 0 on flats.
#include <memory>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

enum class AspectOutput { Degrees, Northness, Eastness };

// From the gradient (dz/dx, dz/dy); `flat` is returned for a zero gradient in Degrees mode.
double aspect_value(double p, double q, AspectOutput output, double flat);

std::shared_ptr<Heightfield> aspect_field(const Heightfield& z, AspectOutput output, double flat,
                                          const ExecContext* ctx = nullptr);

}  // namespace orogen
