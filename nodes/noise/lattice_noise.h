#pragma once
// Single-octave lattice noises in world space: Perlin, Simplex, Value and White.
//
//  - Perlin: improved gradient noise (Perlin 2002): quintic fade 6t^5 - 15t^4 + 10t^3, gradients from a
//    set of 16 unit vectors at 22.5-degree steps (a proper 2D set, not Zaiz 2022's 3D vectors with z
//    dropped, which collapse onto the axes; see noise_reference.h). 0 at every lattice point; C2-continuous.
//    Range [-1, 1] * amplitude.
//  - Simplex: 2D simplex noise (skew F2 = (sqrt3 - 1) / 2, unskew G2 = (3 - sqrt3) / 6), corner
//    contribution max(0, 1/2 - d^2)^4 (g . d), exactly 0 beyond the radius. Range [-1, 1] * amplitude.
//  - Value: random values in [-1, 1] at lattice points, blended with the quintic fade.
//  - White: one random value in [-1, 1] per lattice cell (cell noise); with a feature size at or below the
//    sample spacing this is per-sample white noise, and it stays the same noise at any resolution.
//
// feature_size is the lattice cell size in metres (the wavelength of the dominant features); amplitude is
// in metres. Randomness comes from stream_key(seed, generator) and the lattice coordinates only.
#include <cstdint>

#include "nodes/noise/lattice_hash.h"
#include "nodes/noise/noise_field.h"

namespace orogen::noise {

struct LatticeNoiseParams {
  double feature_size = 256.0;  // m, > 0
  double amplitude = 100.0;     // m; the output spans [-amplitude, amplitude]
  std::uint64_t seed = 0;
};

// Plan for one of Perlin, Simplex, Value, White (not Worley: see worley.h).
NoisePlan lattice_noise_plan(Basis basis, const LatticeNoiseParams& params);

// `inputs` may carry warp_x / warp_y; the other fields are ignored.
Heightfield perlin(const Domain& domain, const LatticeNoiseParams& params, const NoiseInputs& inputs = {},
                   const ExecContext* ctx = nullptr);
Heightfield simplex(const Domain& domain, const LatticeNoiseParams& params, const NoiseInputs& inputs = {},
                    const ExecContext* ctx = nullptr);
Heightfield value_noise(const Domain& domain, const LatticeNoiseParams& params, const NoiseInputs& inputs = {},
                        const ExecContext* ctx = nullptr);
Heightfield white_noise(const Domain& domain, const LatticeNoiseParams& params, const NoiseInputs& inputs = {},
                        const ExecContext* ctx = nullptr);

// The hash stream of a basis (its octaves use octave numbers 0, 1, ...).
Stream basis_stream(Basis basis);

}  // namespace orogen::noise
