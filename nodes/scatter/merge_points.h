#pragma once
// Concatenation of point sets.
#include <vector>

#include "graph/points.h"

namespace orogen {

// The points of every set in order (null entries skipped), with the union of their named attributes; an
// attribute missing from a set is 0 on that set's points.
Points merge_points(const std::vector<const Points*>& sets);

}  // namespace orogen
