#pragma once
// A linear ramp in world space: the value goes from `from` to `to` along a direction, across a span that
// starts at a world point and has a length in metres; it is constant (clamped) before and after the span.
// Independent of the sampling resolution: the value at a world point depends on that point only.
#include <span>

#include "graph/domain.h"
#include "graph/heightfield.h"

namespace orogen {

struct LinearGradientParams {
  double from = 0.0;           // value at the start of the span, metres
  double to = 100.0;           // value at the end of the span, metres
  double angle_deg = 0.0;      // direction of increase: 0 = +x (east), 90 = +y (north), counter-clockwise
  glm::dvec2 start{0.0, 0.0};  // world point where the ramp begins, metres
  double length = 1024.0;      // span length along the direction, metres (> 0)
};

// The ramp's value at world position p.
double linear_gradient_at(const LinearGradientParams& params, glm::dvec2 p);

// Row j of `domain` into `out`.
void linear_gradient_row(const LinearGradientParams& params, const Domain& domain, int j, std::span<float> out);

// The whole field on `domain`.
Heightfield linear_gradient(const LinearGradientParams& params, const Domain& domain);

}  // namespace orogen
