#include "nodes/noise/fbm.h"

#include <algorithm>
#include <cmath>

#include "graph/exec_context.h"
#include "nodes/noise/lattice_hash.h"
#include "nodes/noise/lattice_noise.h"

namespace orogen::noise {

NoisePlan fbm_plan(const FbmParams& p) {
  if (p.basis == Basis::White) throw NodeError("white noise is not a fractal basis");
  if (!(p.feature_size > 0.0)) throw NodeError("feature_size must be positive");
  if (p.octaves < 1 || p.octaves > 16) throw NodeError("octaves must be within 1..16");
  if (!(p.lacunarity > 1.0)) throw NodeError("lacunarity must be greater than 1");
  NoisePlan plan;
  plan.basis = p.basis;  // Worley keeps the plan's defaults: F1, Euclidean, jitter 1
  plan.mode = p.mode;
  plan.offset = static_cast<float>(p.offset);
  plan.lacunarity = static_cast<float>(p.lacunarity);
  plan.roughness = static_cast<float>(p.roughness);
  const Stream stream = basis_stream(p.basis);
  double amplitude_sum = 0.0;
  for (int k = 0; k < p.octaves; ++k) {
    const auto ku = static_cast<std::uint32_t>(k);
    OctavePlan o;
    o.frequency = std::pow(p.lacunarity, k) / p.feature_size;
    if (k > 0) {
      o.shift_x = stream_unit(p.seed, Stream::OctaveOffset, ku, 0);
      o.shift_y = stream_unit(p.seed, Stream::OctaveOffset, ku, 1);
    }
    o.key = stream_key(p.seed, stream, ku);
    const double a = std::pow(p.gain, k);
    o.amplitude = static_cast<float>(a);
    amplitude_sum += a;
    plan.octaves.push_back(o);
  }
  double norm = 1.0;
  switch (p.mode) {
    case FractalMode::Fbm:
    case FractalMode::Billow:
      norm = amplitude_sum;
      break;
    case FractalMode::Ridged: {
      const double peak = std::max(p.offset, 1.0 - p.offset);
      norm = amplitude_sum * std::max(peak * peak, 1e-6);
      break;
    }
    case FractalMode::Hybrid:
      norm = amplitude_sum * std::max(1.0 + p.offset, 1e-6);
      break;
    case FractalMode::Multifractal:
      norm = 1.0;
      break;
  }
  plan.scale = static_cast<float>(p.amplitude / norm);
  return plan;
}

Heightfield fbm(const Domain& d, const FbmParams& p, const NoiseInputs& in, const ExecContext* ctx) {
  return evaluate_noise(d, fbm_plan(p), in, ctx);
}

}  // namespace orogen::noise
