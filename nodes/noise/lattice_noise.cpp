#include "nodes/noise/lattice_noise.h"

#include <stdexcept>

#include "graph/exec_context.h"
#include "nodes/noise/lattice_hash.h"

namespace orogen::noise {

Stream basis_stream(Basis basis) {
  switch (basis) {
    case Basis::Perlin:
      return Stream::Perlin;
    case Basis::Simplex:
      return Stream::Simplex;
    case Basis::Value:
      return Stream::Value;
    case Basis::White:
      return Stream::White;
    case Basis::Worley:
      return Stream::Worley;
  }
  return Stream::Perlin;
}

NoisePlan lattice_noise_plan(Basis basis, const LatticeNoiseParams& p) {
  if (basis == Basis::Worley) throw std::invalid_argument("lattice_noise_plan: use worley_plan for Worley");
  if (!(p.feature_size > 0.0)) throw NodeError("feature_size must be positive");
  NoisePlan plan;
  plan.basis = basis;
  plan.octaves.push_back({1.0 / p.feature_size, 0.0, 0.0, stream_key(p.seed, basis_stream(basis)), 1.0f});
  plan.scale = static_cast<float>(p.amplitude);
  return plan;
}

Heightfield perlin(const Domain& d, const LatticeNoiseParams& p, const NoiseInputs& in, const ExecContext* ctx) {
  return evaluate_noise(d, lattice_noise_plan(Basis::Perlin, p), {in.warp_x, in.warp_y}, ctx);
}
Heightfield simplex(const Domain& d, const LatticeNoiseParams& p, const NoiseInputs& in, const ExecContext* ctx) {
  return evaluate_noise(d, lattice_noise_plan(Basis::Simplex, p), {in.warp_x, in.warp_y}, ctx);
}
Heightfield value_noise(const Domain& d, const LatticeNoiseParams& p, const NoiseInputs& in, const ExecContext* ctx) {
  return evaluate_noise(d, lattice_noise_plan(Basis::Value, p), {in.warp_x, in.warp_y}, ctx);
}
Heightfield white_noise(const Domain& d, const LatticeNoiseParams& p, const NoiseInputs& in, const ExecContext* ctx) {
  return evaluate_noise(d, lattice_noise_plan(Basis::White, p), {in.warp_x, in.warp_y}, ctx);
}

}  // namespace orogen::noise
