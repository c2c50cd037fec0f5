#include "nodes/field/multiply.h"

#include <vector>

#include "graph/exec_context.h"
#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/match_domain.h"
#include "nodes/common/resample.h"

namespace orogen {

void multiply_row(const MultiplyParams& params, std::span<const float> a_row, std::span<const float> b_row,
                  std::span<float> out) {
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = static_cast<float>(params.scale * a_row[i] * b_row[i]);
}

Heightfield multiply_fields(const Heightfield& a, const Heightfield& b, const MultiplyParams& params) {
  Heightfield out(a.domain);
  std::vector<float> b_row(static_cast<std::size_t>(a.width()));
  const bool same = b.domain == a.domain;
  for (int j = 0; j < a.height(); ++j) {
    if (!same) resample_bilinear_row(b, a.domain, j, b_row);
    multiply_row(params, a.row(j), same ? b.row(j) : std::span<const float>(b_row), out.row(j));
  }
  return out;
}

// --- node ---

OROGEN_NODE(Multiply) {
  b.reach_pointwise();
  b.category("field").description(
      "Product of two fields: out = scale * a * b, on a's domain (masking, modulation). If b is sampled on a "
      "different domain it is resampled onto a's bilinearly (values beyond b's rectangle repeat its border).");
  b.input("a", PortType::Heightfield).description("First field; defines the output's domain");
  b.input("b", PortType::Heightfield).description("Second field (often a 0..1 mask)");
  b.output("out", PortType::Heightfield).description("scale * a * b");
  b.param_float("scale", 1.0)
      .range(-1e6, 1e6)
      .soft_range(-10, 10)
      .unit(Unit::Factor)
      .description("Factor applied to the product");
  b.execute([](ExecContext& ctx) {
    const auto a = ctx.require<Heightfield>("a");
    const auto bf = ctx.require<Heightfield>("b");
    const MultiplyParams p{ctx.param<double>("scale")};
    auto out = std::make_shared<Heightfield>(a->domain);
    const bool same = bf->domain == a->domain;
    if (!same) check_overlap(ctx, "b", bf->domain, a->domain);  // b is resampled row by row below
    parallel_rows(ctx, a->height(), [&](int j) {
      if (same) return multiply_row(p, a->row(j), bf->row(j), out->row(j));
      std::vector<float> b_row(static_cast<std::size_t>(a->width()));
      resample_bilinear_row(*bf, a->domain, j, b_row);
      multiply_row(p, a->row(j), b_row, out->row(j));
    });
    ctx.set_output("out", std::move(out));
  });
}

}  // namespace orogen
