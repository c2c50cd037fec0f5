#pragma once
// Normalize: stretch a field so its smallest sample becomes `lo` and its largest `hi`.
#include <memory>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

// The field's minimum maps exactly to lo and its maximum exactly to hi. A flat field becomes lo everywhere.
// NaN samples stay NaN. The range reduction is deterministic (see field_range.h).
std::shared_ptr<Heightfield> normalize_field(const Heightfield& in, double lo, double hi,
                                             const ExecContext* ctx = nullptr);

}  // namespace orogen
