#pragma once
// Product of two fields: out = scale * a * b, on a's domain (masks, attenuation, modulation).
// If b is sampled on another domain, it is first resampled onto a's domain bilinearly (clamped at b's
// borders; see nodes/common/resample.h).
#include <span>

#include "graph/heightfield.h"

namespace orogen {

struct MultiplyParams {
  double scale = 1.0;
};

void multiply_row(const MultiplyParams& params, std::span<const float> a_row, std::span<const float> b_row,
                  std::span<float> out);

Heightfield multiply_fields(const Heightfield& a, const Heightfield& b, const MultiplyParams& params = {});

}  // namespace orogen
