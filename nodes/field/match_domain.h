#pragma once
// Bringing an input onto the domain an operator works on. Two-input operators work on the first input's
// domain and resample the others onto it when they differ (a preview-resolution mask combined with a
// full-resolution height), with the shared bilinear rule of nodes/common/resample.h (exact on coinciding
// lattice samples, clamped beyond the source's rectangle).
#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

// `field` itself when it already lies on `target`, else a resampled copy (rows in parallel). Null stays null.
HeightfieldPtr match_domain(HeightfieldPtr field, const Domain& target, const ExecContext* ctx = nullptr);

}  // namespace orogen
