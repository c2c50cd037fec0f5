// Worley: the node wrapping worley() (worley.h).
#include "graph/registry.h"
#include "nodes/noise/generator_node.h"
#include "nodes/noise/worley.h"

namespace orogen::noise {

OROGEN_NODE(Worley) {
  b.reach_pointwise();
  b.category("noise").description(
      "Worley (cellular) noise: distances to the nearest feature points, one point per cell of side "
      "feature_size. Exact for every metric, output and jitter (the search covers every cell that can hold "
      "one of the four nearest points). S. Worley (1996), \"A cellular texture basis function\", SIGGRAPH.");
  declare_warp_inputs(b);
  b.output("out", PortType::Heightfield)
      .description("The chosen distance function times amplitude, in metres")
      .kind(OutputKind::Height);
  declare_feature_size(b, 256.0, "Spacing of the feature points (lattice cell size)");
  declare_amplitude(b, 100.0, "Metres per lattice cell of distance (F1 * F2: per square cell)");
  b.param_enum("metric", {"euclidean", "manhattan", "chebyshev"}, "euclidean")
      .description("Distance metric: euclidean (round cells), manhattan (diamonds), chebyshev (squares)");
  b.param_enum("output", {"f1", "f2", "f2_minus_f1", "f1_times_f2", "mean_f1_f4"}, "f1")
      .description(
          "Function of the distances F1 <= F2 <= F3 <= F4 to the nearest points: f1 (cells, 0 at "
          "the points), f2, f2_minus_f1 (ridges along the cell borders), f1_times_f2, mean_f1_f4");
  b.param_float("jitter", 1.0)
      .range(0.0, 1.0)
      .unit(Unit::Unitless)
      .description("How far the feature points stray from the cell centers: 0 gives a regular grid, 1 the full cell");
  declare_seed(b);
  b.execute([](ExecContext& ctx) {
    WorleyParams p;
    p.feature_size = ctx.param<double>("feature_size");
    p.amplitude = ctx.param<double>("amplitude");
    p.metric = static_cast<WorleyMetric>(ctx.enum_index("metric"));
    p.output = static_cast<WorleyOutput>(ctx.enum_index("output"));
    p.jitter = ctx.param<double>("jitter");
    p.seed = ctx.param<std::uint64_t>("seed");
    set_field_output(ctx, worley(ctx.domain(), p, warp_inputs(ctx).view(), &ctx));
  });
}

}  // namespace orogen::noise
