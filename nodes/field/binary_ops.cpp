// Subtract, Min, Max: sample-wise combinations of two fields. The result lies on the first input's
// domain; the second input is resampled onto it when the domains differ.
#include <algorithm>

#include "graph/registry.h"
#include "nodes/field/field_map.h"
#include "nodes/common/match_domain.h"

namespace orogen {
namespace {

template <class F>
void run_binary(ExecContext& ctx, F&& f) {
  const auto a = ctx.require<Heightfield>("a");
  const auto b = require_secondary_input<Heightfield>(ctx, "b", a->domain);
  ctx.set_output("out", map_fields(*a, *b, f, &ctx));
}

void declare_binary_ports(NodeBuilder& b, const char* a_text, const char* b_text, const char* out_text,
                          OutputKind kind = OutputKind::Auto) {
  b.input("a", PortType::Heightfield).description(a_text);
  b.input("b", PortType::Heightfield).description(std::string(b_text) + " (resampled onto a's domain if it differs)");
  b.output("out", PortType::Heightfield).description(out_text).kind(kind);
}

}  // namespace

OROGEN_NODE(Subtract) {
  b.reach_pointwise();
  b.category("field").description("Difference of two fields, a - b, sample by sample.");
  declare_binary_ports(b, "Minuend", "Subtrahend", "a - b", OutputKind::Signed);
  b.execute([](ExecContext& ctx) { run_binary(ctx, [](double x, double y) { return x - y; }); });
}

OROGEN_NODE(Min) {
  b.reach_pointwise();
  b.category("field").description("Sample-wise minimum of two fields (intersection of masks, carving).");
  declare_binary_ports(b, "First field", "Second field", "min(a, b)");
  b.execute([](ExecContext& ctx) { run_binary(ctx, [](double x, double y) { return std::min(x, y); }); });
}

OROGEN_NODE(Max) {
  b.reach_pointwise();
  b.category("field").description("Sample-wise maximum of two fields (union of masks, stacking landforms).");
  declare_binary_ports(b, "First field", "Second field", "max(a, b)");
  b.execute([](ExecContext& ctx) { run_binary(ctx, [](double x, double y) { return std::max(x, y); }); });
}

}  // namespace orogen
