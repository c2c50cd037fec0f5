// A small, correct node library for the loader's tests (tests/test_node_library.cpp): one node that works
// and one whose execute throws something that is not a std::exception.
#include <cmath>

#include <orogen/node.h>

using namespace orogen;

OROGEN_NODE(SampleQuantize) {
  b.category("test").description("Heights rounded down to a multiple of a step: flat terraces.");
  b.reach_pointwise();
  b.input("in", PortType::Heightfield).description("Heights, metres");
  b.output("out", PortType::Heightfield).description("Quantized heights, metres");
  b.param_float("step", 10.0).range(0.01, 1e4).unit(Unit::Metre).description("Height of one terrace");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const double step = ctx.param<double>("step");
    auto out = std::make_shared<Heightfield>(in->domain);
    for (std::size_t k = 0; k < in->data.size(); ++k)
      out->data[k] = static_cast<float>(std::floor(in->data[k] / step) * step);
    ctx.set_output("out", out);
  });
}

OROGEN_NODE(SampleThrows) {
  b.category("test").description("Throws an int from its execute function, as a buggy node might.");
  b.reach_pointwise();
  b.input("in", PortType::Heightfield).description("Heights, metres");
  b.output("out", PortType::Heightfield).description("Never produced");
  b.execute([](ExecContext&) { throw 42; });
}
