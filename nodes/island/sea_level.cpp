#include "nodes/island/sea_level.h"

#include <algorithm>
#include <cmath>

#include "graph/exec_context.h"
#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"

namespace orogen::island {

std::shared_ptr<Heightfield> sea_level_normalize(const Heightfield& in, const SeaLevelParams& p,
                                                 const ExecContext* ctx) {
  double hi = p.sea_level, lo = p.sea_level;
  for (float v : in.data)
    if (std::isfinite(v)) {
      hi = std::max(hi, static_cast<double>(v));
      lo = std::min(lo, static_cast<double>(v));
    }
  const double up = hi > p.sea_level ? p.height / (hi - p.sea_level) : 0.0;
  const double down = lo < p.sea_level ? p.depth / (p.sea_level - lo) : 0.0;
  auto out = std::make_shared<Heightfield>(in.domain);
  const auto row = [&](int j) {
    for (int i = 0; i < in.width(); ++i) {
      const double t = static_cast<double>(in.at(i, j)) - p.sea_level;
      out->at(i, j) = static_cast<float>(t > 0.0 ? t * up : t * down);
    }
  };
  if (ctx)
    parallel_rows(*ctx, in.height(), row);
  else
    for (int j = 0; j < in.height(); ++j) row(j);
  return out;
}

OROGEN_NODE(SeaLevelNormalize) {
  b.distribution(Distribution::Reduction);
  b.reach_global();  // the extremes of the whole field
  b.category("island").description(
      "Normalizes a terrain about sea level, as the last step of S. Weiss (2015), \"Procedural Terrain\" "
      "(Georgia Tech CS6491) §IV-F: heights above sea level are scaled so the highest sample reaches `height`, "
      "heights below so the deepest reaches -`depth`; sea level becomes 0 and the coastline stays where it is.");
  b.input("in", PortType::Heightfield).description("Heights, metres");
  b.output("out", PortType::Heightfield).description("Heights, metres, sea level at 0").kind(OutputKind::Height);
  b.param_float("sea_level", 0.0)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .unit(Unit::Metre)
      .description("Sea level in the input");
  b.param_float("height", 1000.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 9000.0)
      .unit(Unit::Metre)
      .description("Height of the highest sample");
  b.param_float("depth", 200.0)
      .range(0.0, 1e5)
      .soft_range(0.0, 9000.0)
      .unit(Unit::Metre)
      .description("Depth of the deepest sample below sea level");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const SeaLevelParams p{ctx.param<double>("sea_level"), ctx.param<double>("height"), ctx.param<double>("depth")};
    ctx.set_output("out", sea_level_normalize(*in, p, &ctx));
  });
}

}  // namespace orogen::island
