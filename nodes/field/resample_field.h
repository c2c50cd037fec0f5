#pragma once
// Resample: the same world rectangle on a lattice with a chosen spacing in metres. Gives a level of detail
// that does not depend on the requested resolution: a terrain mesh, a coarse simulation grid or a preview
// export at a fixed metres-per-sample.
//
// The output has n = max(2, round(size / spacing) + 1) samples per axis over the input's rectangle (so its
// spacing is within half a sample of the request and the borders stay on the input's borders), sampled
// bilinearly (exact where output and input samples coincide). The optional Gaussian prefilter, sigma = half
// the output spacing in metres whatever the input's spacing (so every request resolution is filtered
// alike), removes most of the detail a coarser lattice cannot hold (anti-aliasing: a wave of 1.25 output
// spacings keeps 5% of its amplitude); without it samples keep their exact heights.
#include <memory>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen {

struct ResampleParams {
  double spacing = 16.0;  // m, > 0
  bool prefilter = false;
};

Domain resampled_domain(const Domain& in, double spacing);

std::shared_ptr<Heightfield> resample_field(const Heightfield& in, const ResampleParams& p,
                                            const ExecContext* ctx = nullptr);

}  // namespace orogen
