#pragma once
// Gaussian blur with its standard deviation in metres.
//
// Separable: rows, then columns, each with sigma / spacing samples, so anisotropic spacings blur the same
// world distance in both directions and the result converges as the resolution grows. Two kernels:
// - sigma up to kDirectMaxSigma samples: direct convolution with the sampled Gaussian truncated at 4 sigma
//   and normalised to sum 1;
// - wider: five passes of the extended box filter (Gwosdek, Grewenig, Bruhn, Weickert 2011), whose fractional
//   end taps make the total variance exactly sigma^2, at O(1) per sample whatever the radius. Its kernel
//   differs from the Gaussian by about 1% of the peak.
// Edges: Clamp repeats the edge sample; Mirror reflects about the half-sample beyond the edge
// (..., x1, x0 | x0, x1, ...), which makes the operator symmetric so the sum (and mean) of the field is
// preserved exactly up to rounding. Both preserve a constant field.
#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

enum class BlurEdges { Clamp, Mirror };

struct BlurParams {
  double sigma = 10.0;  // m, standard deviation of the Gaussian; 0 = copy
  BlurEdges edges = BlurEdges::Clamp;
};

inline constexpr double kDirectMaxSigma = 12.0;  // samples

Heightfield gaussian_blur(const Heightfield& in, const BlurParams& params, const ExecContext* ctx = nullptr);

// One line filtered in place-independent buffers, `sigma` in samples (exposed for tests of the kernels).
void gaussian_blur_line(const float* in, float* out, int n, double sigma_samples, BlurEdges edges);

}  // namespace orogen
