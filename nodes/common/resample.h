#pragma once
// Bilinear resampling of a field onto another domain. Used wherever two fields on different lattices meet
// (binary field operators, reading images of another resolution).
//
// Each target sample takes the bilinear interpolation of the source at the same world position; positions
// outside the source's rectangle take the value at the nearest border (clamp). Where a target sample falls
// on a source sample (same lattice, or an integer multiple of it) the source value is copied exactly:
// sample coordinates within 1e-7 of an integer are snapped, so round-off in the world position never blends
// in a neighbour.
#include <span>

#include "graph/domain.h"
#include "graph/heightfield.h"

namespace orogen {

// Row j of `target` resampled from `source` into `out` (target.width() values).
void resample_bilinear_row(const Heightfield& source, const Domain& target, int j, std::span<float> out);

// The whole field on `target` (serial; nodes parallelise over rows with resample_bilinear_row).
Heightfield resample_bilinear(const Heightfield& source, const Domain& target);

}  // namespace orogen
