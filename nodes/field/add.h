#pragma once
// Weighted sum of two fields: out = weight_a * a + weight_b * b, on a's domain.
// If b is sampled on another domain, it is first resampled onto a's domain bilinearly (clamped at b's
// borders; see nodes/common/resample.h).
#include <span>

#include "graph/heightfield.h"

namespace orogen {

struct AddParams {
  double weight_a = 1.0;
  double weight_b = 1.0;
};

// Row j of a's domain; `b_row` is b's row already on a's domain.
void add_row(const AddParams& params, std::span<const float> a_row, std::span<const float> b_row, std::span<float> out);

// The whole sum on a's domain.
Heightfield add_fields(const Heightfield& a, const Heightfield& b, const AddParams& params = {});

}  // namespace orogen
