#pragma once
// Fractal noise: octaves of a basis (Perlin, Simplex, Value or Worley F1) at frequencies
// lacunarity^k / feature_size, combined by one of five modes. Octave k > 0 is shifted by a seeded
// fraction of a cell so the octaves' lattices do not line up (otherwise Perlin octaves all vanish together
// at the coarse lattice points), and hashes octave k with its own key: octave 0 is exactly the single
// generator of the same seed.
//
// With amp_k = gain^k and n_k the basis at octave k:
//  - fbm:     sum amp_k n_k / sum amp_k                                         in [-1, 1]
//  - billow:  sum amp_k (2|n_k| - 1) / sum amp_k                                 in [-1, 1]
//  - ridged:  Musgrave's ridged multifractal: s_k = (offset - |n_k|)^2 * w_k, w_0 = 1,
//             w_k = clamp(2 s_{k-1}, 0, 1); sum amp_k s_k / (sum amp_k * max(offset, 1 - offset)^2), in [0, 1]
//  - hybrid:  Musgrave's hybrid multifractal: s_k = (n_k + offset) amp_k, result = s_0, w = s_0, then
//             w = min(w, 1), result += w s_k, w *= s_k; divided by (1 + offset) sum amp_k (about [0, 1]).
//  - multifractal: Weiss 2015 Eq 4, N = A(x, y) sum_k n_k / r^(k (1 - R(x, y))) with r = lacunarity, R the
//             roughness (field or parameter) and A the amplitude field; not normalised (as in Weiss 2015), so it
//             spans up to +-sum_k r^(-k(1-R)). gain and offset are not used.
// The result is multiplied by `amplitude` (metres) and, when connected, by the amplitude field (all
// modes). For Worley the basis is F1 (Euclidean, jitter 1), in [0, ~1.2] rather than [-1, 1].
#include <cstdint>

#include "nodes/noise/noise_field.h"

namespace orogen::noise {

struct FbmParams {
  Basis basis = Basis::Perlin;  // Perlin, Simplex, Value or Worley
  FractalMode mode = FractalMode::Fbm;
  double feature_size = 1024.0;  // m, > 0: cell size of the first (largest) octave
  double amplitude = 200.0;      // m
  int octaves = 6;               // 1..16
  double lacunarity = 2.0;       // frequency ratio between octaves, > 1
  double gain = 0.5;             // amplitude ratio between octaves (persistence)
  double offset = 1.0;           // ridged and hybrid
  double roughness = 0.5;        // multifractal R where no roughness field is connected, 0..1
  std::uint64_t seed = 0;
};

NoisePlan fbm_plan(const FbmParams& params);

// `inputs`: warp_x / warp_y, roughness (multifractal), amplitude (all modes).
Heightfield fbm(const Domain& domain, const FbmParams& params, const NoiseInputs& inputs = {},
                const ExecContext* ctx = nullptr);

}  // namespace orogen::noise
