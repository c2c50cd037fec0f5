// Constant: a flat field.
#include "graph/exec_context.h"
#include "graph/registry.h"

namespace orogen {

OROGEN_NODE(Constant) {
  b.reach_pointwise();
  b.category("field").description("A flat field: every sample has the same value.");
  b.output("out", PortType::Heightfield).description("The constant field");
  b.param_float("value", 0.0)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .unit(Unit::Metre)
      .description("Value of every sample");
  b.execute([](ExecContext& ctx) {
    ctx.set_output("out", std::make_shared<Heightfield>(ctx.domain(), static_cast<float>(ctx.param<double>("value"))));
  });
}

}  // namespace orogen
