#pragma once
// The evaluation engine shared by every noise generator: a NoisePlan (basis, octaves, how they combine)
// sampled on a Domain.
//
// Each octave samples its basis at lattice coordinates
//   u = (x + warp_x) * frequency + shift_x,   v = (y + warp_y) * frequency + shift_y
// where (x, y) is the world position of the sample (Domain::x(i), Domain::y(j), metres) and warp_x/y are
// optional displacement fields in metres, read at the same sample: the noise is evaluated exactly at the
// displaced position, never resampled. Everything depends only on the global lattice index of a sample,
// so any tile, at any thread count, gives exactly the same values as a larger domain containing it.
//
// Blocks of 8 rows run in parallel; each block is processed in runs of up to 256 columns by the SIMD kernels.
// Unwarped Perlin, Value and White evaluate the rows of a block that fall in the same lattice row together,
// hashing each lattice corner once for all of them (a row's values never depend on its companions).
#include <cstdint>
#include <optional>
#include <vector>

#include "graph/heightfield.h"
#include "nodes/noise/noise_types.h"

namespace orogen {
class ExecContext;
}

namespace orogen::noise {

struct OctavePlan {
  double frequency = 1.0;               // lattice cells per metre
  double shift_x = 0.0, shift_y = 0.0;  // lattice offset, cells (breaks the alignment of octave lattices)
  std::uint32_t key = 0;                // hash key (stream_key of the node seed)
  float amplitude = 1.0f;               // octave weight (fbm, billow, ridged, hybrid)
};

struct NoisePlan {
  Basis basis = Basis::Perlin;
  WorleyMetric worley_metric = WorleyMetric::Euclidean;
  WorleyOutput worley_output = WorleyOutput::F1;
  float worley_jitter = 1.0f;
  FractalMode mode = FractalMode::Fbm;
  std::vector<OctavePlan> octaves;
  float offset = 1.0f;      // ridged and hybrid
  float lacunarity = 2.0f;  // multifractal: the octave factor r of Weiss 2015 Eq 4
  float roughness = 0.5f;   // multifractal: R where no roughness field is given
  float scale = 1.0f;       // multiplies the combined octaves (metres)
};

// Optional per-sample fields, sampled on the requested domain (same resolution).
struct NoiseInputs {
  const Heightfield* warp_x = nullptr;     // metres added to x before sampling
  const Heightfield* warp_y = nullptr;     // metres added to y before sampling
  const Heightfield* roughness = nullptr;  // multifractal R in [0, 1]
  const Heightfield* amplitude = nullptr;  // multiplies the output (Weiss 2015's A)
};

// Throws NodeError if an input field does not have the domain's resolution or the plan is invalid.
Heightfield evaluate_noise(const Domain& domain, const NoisePlan& plan, const NoiseInputs& inputs = {},
                           const ExecContext* ctx = nullptr);
// The same into existing storage: `out` is resized to out.domain (memory is reused when it fits).
void evaluate_noise_into(Heightfield& out, const NoisePlan& plan, const NoiseInputs& inputs = {},
                         const ExecContext* ctx = nullptr);

// Per-sample input values for the scalar reference.
struct ReferenceInputs {
  float warp_x = 0.0f, warp_y = 0.0f;
  std::optional<float> roughness;  // default: plan.roughness
  float amplitude = 1.0f;
};

// The scalar reference of evaluate_noise at world position (x, y) (Worley by brute force).
float evaluate_noise_reference(const NoisePlan& plan, double x, double y, const ReferenceInputs& inputs = {});

}  // namespace orogen::noise
