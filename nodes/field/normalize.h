#pragma once
// Normalize: stretch a field so its smallest sample becomes `lo` and its largest `hi`.
#include <memory>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "nodes/field/field_range.h"

namespace orogen {

// The field's minimum maps exactly to lo and its maximum exactly to hi. A flat field becomes lo everywhere.
// NaN samples stay NaN. The range reduction is deterministic (see field_range.h).
std::shared_ptr<Heightfield> normalize_field(const Heightfield& in, double lo, double hi,
                                             const ExecContext* ctx = nullptr);
// The same with the range given: `range` is the field's (or, in a tiled build, the whole domain's) range.
std::shared_ptr<Heightfield> normalize_field(const Heightfield& in, const ValueRange& range, double lo, double hi,
                                             const ExecContext* ctx = nullptr);

}  // namespace orogen
