#include "nodes/field/field_range.h"

#include <cmath>
#include <limits>
#include <vector>

#include "nodes/common/cancellable_rows.h"

namespace orogen {

ValueRange field_range(const Heightfield& field, const ExecContext* ctx) {
  constexpr float inf = std::numeric_limits<float>::infinity();
  std::vector<float> lo(static_cast<std::size_t>(field.height()), inf), hi(lo.size(), -inf);
  for_each_row(ctx, field.height(), [&](int j) {
    float a = inf, b = -inf;
    for (const float v : field.row(j)) {
      if (!std::isfinite(v)) continue;
      a = v < a ? v : a;
      b = v > b ? v : b;
    }
    lo[static_cast<std::size_t>(j)] = a;
    hi[static_cast<std::size_t>(j)] = b;
  });
  ValueRange r;
  float a = inf, b = -inf;
  for (std::size_t j = 0; j < lo.size(); ++j) {
    a = lo[j] < a ? lo[j] : a;
    b = hi[j] > b ? hi[j] : b;
  }
  if (a <= b) r = {a, b, false};
  return r;
}

}  // namespace orogen
