#pragma once
// The rule of complete breaching (J. B. Lindsay 2016, "Efficient hybrid breaching-filling sink removal methods for
// flow path enforcement in digital elevation models", Hydrological Processes 30) along a defined tree, shared by the
// whole-domain carve (breach_depressions, nodes/hydrology/flow_routing.h) and the carve across tiles
// (nodes/hydrology/tile_breach.h), so both compute the same bits.
//
// The tree: every cell but an outlet drains to its D8 receiver on the epsilon surface of the heights (the least
// surface with a strictly lower neighbour everywhere, FlatMode::Epsilon), which leads out of each depression by the
// shortest way to its spill point and then down the steepest descent: the path a Priority-Flood reaches the pit by,
// defined by the heights alone rather than by the order a flood takes ties in. A pit (a cell that is no outlet and
// has no strictly lower neighbour) sends its height down the tree; a cell higher than what reaches it is lowered to
// that and passes it on (one float ulp lower in epsilon mode, so the channel descends), a cell no higher stops it.
// Every cell then ends at min(its height, the lowest value that reached it): order-free, since each is a minimum.
#include <cmath>
#include <limits>

namespace orogen::hydrology {

// What a cell passes to its receiver: `height` its height, `arrived` the lowest value that reached it from its
// donors (+inf if none), `pit` whether it is a pit.
inline float breach_passed(float height, float arrived, bool pit, bool epsilon) {
  float passed = std::numeric_limits<float>::infinity();
  if (pit) passed = height;
  if (arrived < height && arrived < passed) passed = arrived;
  if (epsilon && passed < std::numeric_limits<float>::infinity())
    passed = std::nextafter(passed, -std::numeric_limits<float>::infinity());
  return passed;
}

}  // namespace orogen::hydrology
