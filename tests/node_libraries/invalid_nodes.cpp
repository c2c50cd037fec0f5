// A node library whose declaration throws, and one that is inconsistent (a default out of its range).
#include <stdexcept>

#include <orogen/node.h>

using namespace orogen;

OROGEN_NODE(InvalidThrowingDeclaration) {
  b.category("test").description("Its declaration throws.");
  throw std::runtime_error("cannot read my configuration");
}

OROGEN_NODE(InvalidRange) {
  b.category("test").description("A default outside its own range.");
  b.reach_pointwise();
  b.output("out", PortType::Heightfield).description("Zero");
  b.param_float("x", 5.0).range(0.0, 1.0).unit(Unit::Unitless).description("Out of range");
  b.execute([](ExecContext& ctx) { ctx.set_output("out", std::make_shared<Heightfield>(ctx.domain())); });
}
