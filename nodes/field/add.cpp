#include "nodes/field/add.h"

#include <vector>

#include "graph/exec_context.h"
#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/match_domain.h"
#include "nodes/common/resample.h"

namespace orogen {

void add_row(const AddParams& params, std::span<const float> a_row, std::span<const float> b_row,
             std::span<float> out) {
  for (std::size_t i = 0; i < out.size(); ++i)
    out[i] = static_cast<float>(params.weight_a * a_row[i] + params.weight_b * b_row[i]);
}

Heightfield add_fields(const Heightfield& a, const Heightfield& b, const AddParams& params) {
  Heightfield out(a.domain);
  std::vector<float> b_row(static_cast<std::size_t>(a.width()));
  const bool same = b.domain == a.domain;
  for (int j = 0; j < a.height(); ++j) {
    if (!same) resample_bilinear_row(b, a.domain, j, b_row);
    add_row(params, a.row(j), same ? b.row(j) : std::span<const float>(b_row), out.row(j));
  }
  return out;
}

// --- node ---

OROGEN_NODE(Add) {
  b.reach_pointwise();
  b.category("field").description(
      "Weighted sum of two fields: out = weight_a * a + weight_b * b, on a's domain. If b is sampled on a "
      "different domain it is resampled onto a's bilinearly (values beyond b's rectangle repeat its border).");
  b.input("a", PortType::Heightfield).description("First field; defines the output's domain");
  b.input("b", PortType::Heightfield).description("Second field");
  b.output("out", PortType::Heightfield).description("weight_a * a + weight_b * b");
  b.param_float("weight_a", 1.0)
      .range(-1e6, 1e6)
      .soft_range(-10, 10)
      .unit(Unit::Factor)
      .description("Factor applied to a");
  b.param_float("weight_b", 1.0)
      .range(-1e6, 1e6)
      .soft_range(-10, 10)
      .unit(Unit::Factor)
      .description("Factor applied to b");
  b.execute([](ExecContext& ctx) {
    const auto a = ctx.require<Heightfield>("a");
    const auto bf = ctx.require<Heightfield>("b");
    const AddParams p{ctx.param<double>("weight_a"), ctx.param<double>("weight_b")};
    auto out = std::make_shared<Heightfield>(a->domain);
    const bool same = bf->domain == a->domain;
    if (!same) check_overlap(ctx, "b", bf->domain, a->domain);  // b is resampled row by row below
    parallel_rows(ctx, a->height(), [&](int j) {
      if (same) return add_row(p, a->row(j), bf->row(j), out->row(j));
      std::vector<float> b_row(static_cast<std::size_t>(a->width()));
      resample_bilinear_row(*bf, a->domain, j, b_row);
      add_row(p, a->row(j), b_row, out->row(j));
    });
    ctx.set_output("out", std::move(out));
  });
}

}  // namespace orogen
