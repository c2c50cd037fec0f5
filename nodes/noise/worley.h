#pragma once
// Worley (cellular) noise in world space (SeamScape): one feature point per lattice cell of side
// feature_size, placed at the cell centre plus jitter * (uniform - 1/2) on each axis. The output is a
// function of the distances F1 <= F2 <= F3 <= F4 from the sample to the nearest feature points, measured in
// lattice cells and multiplied by amplitude (metres).
//
// Exact: the kernels visit every cell that can hold one of the k nearest points for the chosen metric and
// jitter (worley_neighbourhood.h proves the bound); tests compare with a brute-force search.
//
// Ranges (jitter 1, in cells): Euclidean F1 <= sqrt(2), Manhattan F1 <= 2, Chebyshev F1 <= 1; F2 - F1 >= 0;
// F1 = 0 exactly at the feature points.
#include <cstdint>

#include "nodes/noise/noise_field.h"

namespace orogen::noise {

struct WorleyParams {
  double feature_size = 256.0;  // m, > 0: spacing of the feature points
  double amplitude = 100.0;     // m per lattice cell of distance
  WorleyMetric metric = WorleyMetric::Euclidean;
  WorleyOutput output = WorleyOutput::F1;
  double jitter = 1.0;  // 0 (regular grid of points) .. 1 (anywhere in the cell)
  std::uint64_t seed = 0;
};

NoisePlan worley_plan(const WorleyParams& params);

// `inputs` may carry warp_x / warp_y.
Heightfield worley(const Domain& domain, const WorleyParams& params, const NoiseInputs& inputs = {},
                   const ExecContext* ctx = nullptr);

}  // namespace orogen::noise
