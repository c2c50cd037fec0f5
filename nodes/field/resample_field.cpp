#include "nodes/field/resample_field.h"

#include <algorithm>
#include <cmath>

#include "graph/cost_query.h"
#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/resample.h"
#include "nodes/field/blur.h"

namespace orogen {

Domain resampled_domain(const Domain& in, double spacing) {
  const glm::dvec2 size = in.size();
  const auto count = [&](double extent) {
    return static_cast<int>(std::clamp(std::llround(extent / spacing) + 1, 2LL, 1LL << 20));
  };
  return Domain::from_extent(in.min_corner(), size, {count(size.x), count(size.y)});
}

std::shared_ptr<Heightfield> resample_field(const Heightfield& in, const ResampleParams& p, const ExecContext* ctx) {
  const Domain target = resampled_domain(in.domain, p.spacing);
  const Heightfield* source = &in;
  Heightfield filtered;
  if (p.prefilter) {
    // Fixed in metres (not derived from the input's spacing), so every input resolution is filtered alike.
    const double sigma = 0.5 * std::max(target.spacing.x, target.spacing.y);
    filtered = gaussian_blur(in, {sigma, BlurEdges::Mirror}, ctx);
    source = &filtered;
  }
  auto out = std::make_shared<Heightfield>(target);
  for_each_row(ctx, target.height(), [&](int j) { resample_bilinear_row(*source, target, j, out->row(j)); });
  return out;
}

OROGEN_NODE(Resample) {
  b.version(2);  // 2: the decimated blur aligned to the global lattice (tile-exact)
  b.distribution(Distribution::Gathered);
  b.reach_global();  // the output lattice spans the requested rectangle
  b.own_lattice();
  b.category("field").description(
      "The same world rectangle at a chosen spacing in metres (about size / spacing + 1 samples per axis), "
      "whatever resolution was requested: a fixed level of detail for meshes, exports or coarse simulations. "
      "Bilinear, exact where samples coincide; the optional Gaussian prefilter (sigma = half the output "
      "spacing, mirrored edges) anti-aliases when the output is coarser than the input.");
  b.input("in", PortType::Heightfield).description("Field to resample");
  b.output("out", PortType::Heightfield).description("The field on the new lattice");
  b.param_float("spacing", 16.0)
      .range(1e-3, 1e6)
      .soft_range(0.5, 256.0)
      .unit(Unit::Metre)
      .description("Distance between output samples");
  b.param_bool("prefilter", false).description("Blur away detail finer than the output spacing before sampling");
  // Its output lies on its own lattice: sized by spacing, not by the request (own_lattice).
  b.extra_bytes([](const CostQuery& q) {
    // The input's rectangle (the request's, before the input exists) at the chosen spacing.
    const PortValue* in = q.input("in");
    const Domain& from = in ? std::get<HeightfieldPtr>(*in)->domain : q.domain;
    const Domain lattice = resampled_domain(from, q.params.get<double>("spacing"));
    const double samples = static_cast<double>(lattice.resolution.x) * lattice.resolution.y;
    // The output and a prefiltered copy of the input when asked.
    return per_item_bytes(samples, 4.0) +
           (q.params.get<bool>("prefilter") ? per_item_bytes(static_cast<double>(from.sample_count()), 8.0) : 0);
  });
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const ResampleParams p{ctx.param<double>("spacing"), ctx.param<bool>("prefilter")};
    const Domain target = resampled_domain(in->domain, p.spacing);
    if (target.sample_count() > (std::size_t{1} << 28))
      throw NodeError("Resample: " + target.describe() + " is too many samples; increase the spacing");
    ctx.set_output("out", resample_field(*in, p, &ctx));
  });
}

}  // namespace orogen
