// FBM: the node wrapping fbm() (fbm.h).
#include "graph/registry.h"
#include "nodes/noise/fbm.h"
#include "nodes/common/match_domain.h"
#include "nodes/noise/generator_node.h"

namespace orogen::noise {

namespace {

constexpr Basis kFbmBases[] = {Basis::Perlin, Basis::Simplex, Basis::Value, Basis::Worley};

}  // namespace

OROGEN_NODE(FBM) {
  b.reach_pointwise();
  b.category("noise").description(
      "Fractal noise: octaves of a basis at frequencies lacunarity^k / feature_size and amplitudes gain^k, "
      "combined as fbm, ridged or hybrid multifractal, billow, or a multifractal whose octave weights "
      "r^(-k(1-R)) follow a roughness map R (a spatially varying spectral exponent), after F. K. Musgrave "
      "(2003), \"Procedural fractal terrains\", in Ebert et al., Texturing and Modeling: A Procedural "
      "Approach, 3rd ed.");
  declare_warp_inputs(b);
  b.input("roughness", PortType::Heightfield)
      .optional()
      .description(
          "Multifractal mode: roughness R in [0, 1] per sample (0 smooth, 1 every octave at full "
          "weight); replaces the roughness parameter where connected");
  b.input("amplitude", PortType::Heightfield)
      .optional()
      .description("Multiplies the output per sample (an amplitude map), in every mode");
  b.output("out", PortType::Heightfield).description("The fractal noise, in metres").kind(OutputKind::Height);
  b.param_enum("basis", {"perlin", "simplex", "value", "worley"}, "perlin")
      .description("Noise of each octave; worley uses F1 (Euclidean, jitter 1)");
  b.param_enum("mode", {"fbm", "ridged", "billow", "hybrid", "multifractal"}, "fbm")
      .description(
          "How octaves combine: fbm (sum, [-1, 1]), ridged (sharp crests, [0, 1]), billow (|noise|, "
          "rounded hills), hybrid (Musgrave hybrid multifractal: smooth valleys, rough peaks), "
          "multifractal (octave weights r^(-k(1-R)) from the roughness R)");
  declare_feature_size(b, 1024.0, "Cell size of the first (largest) octave");
  declare_amplitude(b, 200.0, "Output scale in metres (fbm spans [-amplitude, amplitude])");
  b.param_int("octaves", 6).unit(Unit::Count).range(1, 16).description("Number of octaves");
  b.param_float("lacunarity", 2.0)
      .range(1.01, 4.0)
      .unit(Unit::Unitless)
      .description("Frequency ratio r between successive octaves");
  b.param_float("gain", 0.5)
      .range(0.0, 1.0)
      .unit(Unit::Unitless)
      .description("Amplitude ratio between successive octaves (persistence); not used by multifractal");
  b.param_float("offset", 1.0)
      .range(0.0, 2.0)
      .unit(Unit::Unitless)
      .description("Ridged: the ridge height offset - |noise|; hybrid: added to the noise before weighting");
  b.param_float("roughness", 0.5)
      .range(0.0, 1.0)
      .unit(Unit::Unitless)
      .description("Multifractal: roughness R where no roughness field is connected (typically 0.1 to 0.7)");
  declare_seed(b);
  b.execute([](ExecContext& ctx) {
    FbmParams p;
    p.basis = kFbmBases[ctx.enum_index("basis")];
    p.mode = static_cast<FractalMode>(ctx.enum_index("mode"));
    p.feature_size = ctx.param<double>("feature_size");
    p.amplitude = ctx.param<double>("amplitude");
    p.octaves = static_cast<int>(ctx.param<std::int64_t>("octaves"));
    p.lacunarity = ctx.param<double>("lacunarity");
    p.gain = ctx.param<double>("gain");
    p.offset = ctx.param<double>("offset");
    p.roughness = ctx.param<double>("roughness");
    p.seed = ctx.param<std::uint64_t>("seed");
    GeneratorInputs in = warp_inputs(ctx);
    in.roughness = secondary_input<Heightfield>(ctx, "roughness", ctx.domain());
    in.amplitude = secondary_input<Heightfield>(ctx, "amplitude", ctx.domain());
    set_field_output(ctx, fbm(ctx.domain(), p, in.view(), &ctx));
  });
}

}  // namespace orogen::noise
