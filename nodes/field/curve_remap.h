#pragma once
// Curve: a monotone cubic transfer function applied on a normalised range.
//
// A value h is normalised to t = (h - lo) / (hi - lo), clamped to [0, 1], mapped through the curve (whose
// control points live in the unit square), and scaled back: out = lo + curve(t) * (hi - lo). So the curve
// edits the shape of the height distribution inside [lo, hi] without moving the range, the identity curve
// is the identity on [lo, hi], and values outside the range are clamped to curve(0) / curve(1).
#include <memory>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/param_value.h"

namespace orogen {

double curve_remap_value(double h, const CurveValue& curve, double lo, double hi);

// [lo, hi] with lo < hi; the node takes it from its parameters or from the field's own min and max.
std::shared_ptr<Heightfield> curve_remap(const Heightfield& in, const CurveValue& curve, double lo, double hi,
                                         const ExecContext* ctx = nullptr);

}  // namespace orogen
