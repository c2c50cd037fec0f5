// Perlin: the node wrapping perlin() (lattice_noise.h).
#include "graph/registry.h"
#include "nodes/noise/generator_node.h"
#include "nodes/noise/lattice_noise.h"

namespace orogen::noise {

OROGEN_NODE(Perlin) {
  b.category("noise").description(
      "Improved Perlin gradient noise (quintic fade, 16 unit gradients at 22.5-degree steps): smooth "
      "hills, 0 at every lattice point, within [-amplitude, amplitude].");
  declare_warp_inputs(b);
  b.output("out", PortType::Heightfield).description("The noise, in metres");
  declare_feature_size(b, 256.0, "Lattice cell size: the wavelength of the dominant features");
  declare_amplitude(b, 100.0, "Output scale: the noise spans [-amplitude, amplitude]");
  declare_seed(b);
  b.execute([](ExecContext& ctx) {
    const LatticeNoiseParams p{ctx.param<double>("feature_size"), ctx.param<double>("amplitude"),
                               ctx.param<std::uint64_t>("seed")};
    set_field_output(ctx, perlin(ctx.domain(), p, warp_inputs(ctx), &ctx));
  });
}

}  // namespace orogen::noise
