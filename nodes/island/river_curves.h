#pragma once
// The rivers of a polygon map (corner attributes river = volume, downstream = next corner, elevation) as
// polylines: one curve from each source or confluence to the next confluence or the end of the path (the
// coast); parent = the curve that starts where this one ends. z = elevation (m), width = river_width *
// sqrt(volume) (m), attribute volume.
#include "graph/curves.h"
#include "graph/polygon_map.h"

namespace orogen::island {

Curves river_curves(const PolygonMap& map, double river_width);

}  // namespace orogen::island
