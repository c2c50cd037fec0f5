#include "nodes/noise/generator_node.h"

#include "nodes/common/match_domain.h"

namespace orogen::noise {

void declare_warp_inputs(NodeBuilder& b) {
  b.input("warp_x", PortType::Heightfield)
      .optional()
      .description(
          "Displacement added to the x of every sample before the noise is evaluated (metres); the "
          "noise is computed exactly at the displaced position, not resampled");
  b.input("warp_y", PortType::Heightfield)
      .optional()
      .description("Displacement added to the y of every sample before the noise is evaluated (metres)");
}

void declare_feature_size(NodeBuilder& b, double default_metres, const char* description) {
  b.param_float("feature_size", default_metres)
      .range(0.001, 1e7)
      .soft_range(1.0, 20000.0)
      .unit(Unit::Metre)
      .description(description);
}

void declare_amplitude(NodeBuilder& b, double default_metres, const char* description) {
  b.param_float("amplitude", default_metres)
      .range(-1e6, 1e6)
      .soft_range(0.0, 2000.0)
      .unit(Unit::Metre)
      .description(description);
}

void declare_seed(NodeBuilder& b) {
  b.param_seed("seed", 0).description(
      "Seed of the random lattice; the same seed gives the same noise at every resolution and for every tile");
}

void declare_lattice_generator(NodeBuilder& b, const char* description, const char* feature_size_description,
                               LatticeGenerator generate) {
  b.category("noise").description(description);
  declare_warp_inputs(b);
  b.output("out", PortType::Heightfield).description("The noise, in metres").kind(OutputKind::Height);
  declare_feature_size(b, 256.0, feature_size_description);
  declare_amplitude(b, 100.0, "Output scale: the noise spans [-amplitude, amplitude]");
  declare_seed(b);
  b.execute([generate](ExecContext& ctx) {
    const LatticeNoiseParams p{ctx.param<double>("feature_size"), ctx.param<double>("amplitude"),
                               ctx.param<std::uint64_t>("seed")};
    set_field_output(ctx, generate(ctx.domain(), p, warp_inputs(ctx).view(), &ctx));
  });
}

GeneratorInputs warp_inputs(const ExecContext& ctx) {
  GeneratorInputs in;
  in.warp_x = secondary_input<Heightfield>(ctx, "warp_x", ctx.domain());
  in.warp_y = secondary_input<Heightfield>(ctx, "warp_y", ctx.domain());
  return in;
}

}  // namespace orogen::noise
