#pragma once
// Cutting a raster or points value down to a smaller domain of the same lattice: how a tiled build hands a node's
// inputs, computed on a larger (halo-expanded) domain, to a node evaluated on its own domain.
#include "graph/domain.h"
#include "graph/port_value.h"

namespace orogen {

// True if `inner` lies on the lattice of `outer` (same origin and spacing) and within its samples.
bool domain_contains(const Domain& outer, const Domain& inner);

// The part of `value` (a Heightfield or an Image) on `target`, when its domain contains `target` on the same
// lattice; `value` itself when it already lies on `target`, is of another type, or is on another lattice
// (the node then resamples it as usual).
PortValue crop_to_domain(const PortValue& value, const Domain& target);

// The points of `value` (Points computed on `source`) inside `target`'s rectangle, borders included, when `source`
// contains `target` and is larger: how a node evaluated on a tile gets its part of points computed on the whole
// domain. `value` itself otherwise (other types, or the same domain: an untiled build never drops a point).
PortValue crop_points_to_domain(const PortValue& value, const Domain& source, const Domain& target);

// A node's input `value` (computed on `source`) as a node on `target` takes it: rasters by crop_to_domain, points
// by crop_points_to_domain.
PortValue crop_input(const PortValue& value, const Domain& source, const Domain& target);

}  // namespace orogen
