#pragma once
// Colour ramp: a field mapped to colours through a gradient, t = (h - lo) / (hi - lo), colour =
// gradient(t) (stops clamp beyond 0 and 1). The output is a linear RGBA Image.
#include <memory>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/param_value.h"

namespace orogen {

std::shared_ptr<Image> color_ramp(const Heightfield& in, const GradientValue& gradient, double lo, double hi,
                                  const ExecContext* ctx = nullptr);

// Height colour bands after Zaiz 2022's colour map, over heights -100..900 m (positions = (h + 100) / 1000):
// deep water, shallow water up to a hard shoreline at 0 m, sand to 12 m, grass, forest from about 250 m,
// rock from 500 m, snow above 800 m. Linear RGB.
GradientValue terrain_height_gradient();
inline constexpr double kTerrainGradientMin = -100.0;  // m
inline constexpr double kTerrainGradientMax = 900.0;   // m

}  // namespace orogen
