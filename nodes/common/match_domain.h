#pragma once
// The one rule for rasters on different grids. A node with several raster inputs works on the domain of its
// primary input (`in`, or `a` for binary operators; a generator without one works on its requested domain).
// Every secondary raster input (a mask, rainfall, a weight image, ...) is brought onto that domain in world
// space: left as it is when it already lies on it, else resampled bilinearly with the shared rule of
// nodes/common/resample.h (exact on coinciding lattice samples, clamped beyond the secondary's rectangle).
// A secondary input that does not overlap the primary domain at all cannot be resampled: the node fails with
// no_overlap_message, naming the node and the port. (Placement nodes whose primary is not a raster sample
// their fields at each point's world position instead, and check only the overlap.)
#include <memory>
#include <string>
#include <string_view>

#include "graph/domain.h"
#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/image.h"

namespace orogen {

// `field` itself when it already lies on `target`, else a resampled copy (rows in parallel). Null stays null.
HeightfieldPtr match_domain(HeightfieldPtr field, const Domain& target, const ExecContext* ctx = nullptr);
ImagePtr match_domain(ImagePtr image, const Domain& target, const ExecContext* ctx = nullptr);

// Whether the two closed world rectangles share at least one point.
bool domains_overlap(const Domain& a, const Domain& b);

// The one message for a secondary raster that cannot be resampled: "<Type> '<id>': input '<port>' (<its
// domain>) does not overlap the node's grid (<primary>), so it cannot be resampled onto it".
std::string no_overlap_message(const ExecContext& ctx, std::string_view port, const Domain& field,
                               const Domain& primary);

// Throws NodeError(no_overlap_message) unless `field` overlaps `primary`.
void check_overlap(const ExecContext& ctx, std::string_view port, const Domain& field, const Domain& primary);

// The raster on input `port` (T = Heightfield or Image) brought onto `primary`: null when the optional input is
// unconnected, the value itself when it already lies on `primary`, else a resampled copy. Throws NodeError
// (no_overlap_message) when it does not overlap `primary`.
template <class T>
std::shared_ptr<const T> secondary_input(const ExecContext& ctx, std::string_view port, const Domain& primary);
// The same for a required input: throws NodeError when nothing is connected.
template <class T>
std::shared_ptr<const T> require_secondary_input(const ExecContext& ctx, std::string_view port, const Domain& primary);

// For placement nodes, whose primary is not a raster (points at world positions): the field on `port` as it is
// (they sample it at each point's position), null when unconnected, after the same overlap check against the
// node's rectangle `primary`.
HeightfieldPtr world_sampled_input(const ExecContext& ctx, std::string_view port, const Domain& primary);

// Precondition of the library functions that read a secondary raster sample by sample: it must have the
// primary's sample counts (nodes guarantee it with secondary_input). Throws std::invalid_argument naming
// `what` otherwise.
void require_same_grid(const Domain& field, const Domain& primary, std::string_view what);

}  // namespace orogen
