// White: the node wrapping white_noise() (lattice_noise.h).
#include "graph/registry.h"
#include "nodes/noise/generator_node.h"
#include "nodes/noise/lattice_noise.h"

namespace orogen::noise {

OROGEN_NODE(White) {
  b.category("noise").description(
      "White (cell) noise: one independent random value in [-1, 1] per square cell of side "
      "feature_size, times amplitude. With feature_size at or below the sample spacing it is per-sample "
      "white noise that stays the same noise at any resolution.");
  declare_warp_inputs(b);
  b.output("out", PortType::Heightfield).description("The noise, in metres");
  declare_feature_size(b, 256.0, "Side of the square cells that each get one random value");
  declare_amplitude(b, 100.0, "Output scale: the noise spans [-amplitude, amplitude]");
  declare_seed(b);
  b.execute([](ExecContext& ctx) {
    const LatticeNoiseParams p{ctx.param<double>("feature_size"), ctx.param<double>("amplitude"),
                               ctx.param<std::uint64_t>("seed")};
    set_field_output(ctx, white_noise(ctx.domain(), p, warp_inputs(ctx), &ctx));
  });
}

}  // namespace orogen::noise
