#pragma once
// The smallest and largest sample of a field (NaNs ignored). Computed per row, then reduced in row order:
// min and max are exact, so the result is the same for any thread count.
#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

struct ValueRange {
  double min = 0.0;
  double max = 0.0;
  bool empty = true;  // no finite sample
};

ValueRange field_range(const Heightfield& field, const ExecContext* ctx = nullptr);

}  // namespace orogen
