#pragma once
// Bilinear resampling of a field or an image onto another domain. Used wherever two rasters on different
// lattices meet (secondary inputs, see match_domain.h; reading images of another resolution).
//
// Each target sample takes the bilinear interpolation of the source at the same world position; positions
// outside the source's rectangle take the value at the nearest border (clamp). Where a target sample falls
// on a source sample (same lattice, or an integer multiple of it) the source value is copied exactly:
// sample coordinates within 1e-7 of an integer are snapped, so round-off in the world position never blends
// in a neighbour.
#include <span>
#include <vector>

#include "graph/domain.h"
#include "graph/heightfield.h"
#include "graph/image.h"

namespace orogen {

// Row j of `target` resampled from `source` into `out` (target.width() values).
void resample_bilinear_row(const Heightfield& source, const Domain& target, int j, std::span<float> out);

// The whole field on `target` (serial; nodes parallelise over rows with resample_bilinear_row).
Heightfield resample_bilinear(const Heightfield& source, const Domain& target);

// The two rows of a source lattice that row j of `target` reads (`upper` is `lower` + 1, clamped; both -1
// when the row's position is not a number), for sources streamed a band at a time (a file read row by row).
struct BilinearRows {
  int lower = -1, upper = -1;
  double v = 0.0;  // the row coordinate, snapped and clamped
};
BilinearRows bilinear_rows(const Domain& source, const Domain& target, int j);
// The columns of a source lattice that each column of `target` reads, the same for every row: the left one and
// the weight of the right one (column -1 where the position is not a number).
struct BilinearColumns {
  std::vector<int> left;
  std::vector<double> weight;
};
BilinearColumns bilinear_columns(const Domain& source, const Domain& target);
// Row j of `target` from the two rows `rows` names of a field on `source` (source.width() values each): the
// values resample_bilinear_row gives from the whole field, bit for bit. With the columns computed once, a row
// costs only its arithmetic.
void resample_bilinear_row(const Domain& source, std::span<const float> lower, std::span<const float> upper,
                           const BilinearRows& rows, const Domain& target, std::span<float> out);
void resample_bilinear_row(const BilinearColumns& columns, std::span<const float> lower, std::span<const float> upper,
                           const BilinearRows& rows, std::span<float> out);

// One channel of an image at continuous sample coordinates (column u, row v), bilinear, clamped at the
// borders like Heightfield::bilinear (NaN coordinates give NaN).
float image_bilinear(const Image& image, int channel, double u, double v);

// Row j of `target` resampled from every channel of `source` into `out` (target.width() * channels values,
// interleaved), by the same rule as fields.
void resample_bilinear_row(const Image& source, const Domain& target, int j, std::span<float> out);

// The whole image on `target`, channel names kept (serial).
Image resample_bilinear(const Image& source, const Domain& target);

}  // namespace orogen
