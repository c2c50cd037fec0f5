#include "nodes/noise/worley.h"

#include "graph/exec_context.h"
#include "nodes/noise/lattice_hash.h"

namespace orogen::noise {

NoisePlan worley_plan(const WorleyParams& p) {
  if (!(p.feature_size > 0.0)) throw NodeError("feature_size must be positive");
  if (!(p.jitter >= 0.0 && p.jitter <= 1.0)) throw NodeError("jitter must be within [0, 1]");
  NoisePlan plan;
  plan.basis = Basis::Worley;
  plan.worley_metric = p.metric;
  plan.worley_output = p.output;
  plan.worley_jitter = static_cast<float>(p.jitter);
  plan.octaves.push_back({1.0 / p.feature_size, 0.0, 0.0, stream_key(p.seed, Stream::Worley), 1.0f});
  plan.scale = static_cast<float>(p.amplitude);
  return plan;
}

Heightfield worley(const Domain& d, const WorleyParams& p, const NoiseInputs& in, const ExecContext* ctx) {
  return evaluate_noise(d, worley_plan(p), {in.warp_x, in.warp_y}, ctx);
}

}  // namespace orogen::noise
