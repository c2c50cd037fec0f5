#pragma once
// Gaussian blur with its standard deviation in metres.
//
// Separable: rows, then columns, each with sigma / spacing samples, so anisotropic spacings blur the same
// world distance in both directions and the result converges as the resolution grows. Two evaluations:
// - sigma up to kDirectMaxSigma samples: direct convolution with the sampled Gaussian truncated at 4 sigma
//   and normalised to sum 1 (O(sigma) per sample);
// - wider: decimation by an odd factor f ~ sigma / 5 (three box passes of width f against aliasing, whose
//   variance counts towards sigma^2), the exact Gaussian on the coarse line (>= 5 coarse samples of sigma),
//   and Catmull-Rom interpolation back: O(1) per sample whatever sigma, within 3e-4 of the peak of the true
//   Gaussian response like the direct kernel (checked against it in the tests).
// Edges: Clamp repeats the edge sample; Mirror reflects the field about the edge samples
// (..., x2, x1 | x0, x1, x2, ...), i.e. about the domain's world edges, so it behaves the same at any
// resolution. Mirror makes the direct operator symmetric on the periodic mirrored signal, which preserves the
// field's integral (the trapezoid sum, border samples weighted 1/2, as they are shared with neighbouring
// tiles) exactly up to rounding, and to about 1e-5 with the decimated evaluation. Both preserve a constant.
#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

enum class BlurEdges { Clamp, Mirror };

struct BlurParams {
  double sigma = 10.0;  // m, standard deviation of the Gaussian; 0 = copy
  BlurEdges edges = BlurEdges::Clamp;
};

inline constexpr double kDirectMaxSigma = 15.0;  // samples

Heightfield gaussian_blur(const Heightfield& in, const BlurParams& params, const ExecContext* ctx = nullptr);

// One line filtered in place-independent buffers, `sigma` in samples (exposed for tests of the kernels).
// `first` is the global lattice index of in[0] (Domain::first): the decimated evaluation places its coarse
// samples on every f-th global index, so a line cut out of a longer one gives bit-identical results away
// from its ends (tiling).
void gaussian_blur_line(const float* in, float* out, int n, double sigma_samples, BlurEdges edges, long first = 0);

// How far the blur reaches, in metres, for sigma in metres; with 2 more samples this bounds both
// evaluations (direct: ceil(4 sigma) samples; decimated: under 4.9 sigma).
inline double blur_reach_metres(double sigma) { return 5.0 * sigma; }

}  // namespace orogen
