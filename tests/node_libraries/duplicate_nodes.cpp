// A node library that declares a type Orogen already has (Slope): refused as a whole at load.
#include <orogen/node.h>

using namespace orogen;

OROGEN_NODE(DuplicateFine) {
  b.category("test").description("A correct node of a library that is refused for its other type.");
  b.reach_pointwise();
  b.output("out", PortType::Heightfield).description("Zero, metres");
  b.execute([](ExecContext& ctx) { ctx.set_output("out", std::make_shared<Heightfield>(ctx.domain())); });
}

OROGEN_NODE(Slope) {
  b.category("test").description("Collides with the built-in Slope node type.");
  b.reach_pointwise();
  b.output("out", PortType::Heightfield).description("Zero");
  b.execute([](ExecContext& ctx) { ctx.set_output("out", std::make_shared<Heightfield>(ctx.domain())); });
}
