// Small node types for the editor tests, so they do not depend on the real node library: a source, a
// blend with an optional second input, a Points producer (for type mismatches) and a slow node that
// honours cancellation.
#include <chrono>
#include <cmath>
#include <thread>

#include "graph/exec_context.h"
#include "graph/registry.h"

namespace orogen {

OROGEN_NODE(EdSource) {
  b.category("test").description("Editor test source: a tilted plane plus a seeded offset.");
  b.output("out", PortType::Heightfield).description("The plane");
  b.param_float("height", 10.0).range(-1e4, 1e4).soft_range(0, 100).unit(Unit::Metre).description("Base height");
  b.param_float("tilt", 0.01).range(-1, 1).unit(Unit::MetrePerMetre).description("Slope along x");
  b.param_seed("seed", 1).description("Seed of the offset");
  b.execute([](ExecContext& ctx) {
    auto h = std::make_shared<Heightfield>(ctx.domain());
    const double base = ctx.param<double>("height") + static_cast<double>(ctx.param<std::uint64_t>("seed") % 7);
    const double tilt = ctx.param<double>("tilt");
    for (int j = 0; j < h->height(); ++j)
      for (int i = 0; i < h->width(); ++i) h->at(i, j) = static_cast<float>(base + tilt * ctx.domain().x(i));
    ctx.set_output("out", h);
  });
}

OROGEN_NODE(EdBlend) {
  b.category("test").description("Editor test blend: a + weight * b.");
  b.input("a", PortType::Heightfield).description("First field");
  b.input("b", PortType::Heightfield).optional().description("Second field");
  b.output("out", PortType::Heightfield).description("The blend");
  b.param_float("weight", 0.5).unit(Unit::Unitless).range(0, 1).description("Weight of b");
  b.param_enum("mode", {"add", "max"}, "add").description("How b is combined");
  b.execute([](ExecContext& ctx) {
    auto a = ctx.require<Heightfield>("a");
    auto out = std::make_shared<Heightfield>(*a);
    if (auto bb = ctx.input<Heightfield>("b")) {
      const float w = static_cast<float>(ctx.param<double>("weight"));
      const bool max = ctx.enum_index("mode") == 1;
      for (std::size_t k = 0; k < out->data.size(); ++k)
        out->data[k] = max ? std::max(out->data[k], w * bb->data[k]) : out->data[k] + w * bb->data[k];
    }
    ctx.set_output("out", out);
  });
}

OROGEN_NODE(EdScatter) {
  b.category("test").description("Editor test scatter: points on a regular grid over the field.");
  b.input("height", PortType::Heightfield).description("Terrain");
  b.output("points", PortType::Points).description("The points");
  b.param_int("count", 4).unit(Unit::Count).range(1, 64).description("Points per side");
  b.execute([](ExecContext& ctx) {
    auto h = ctx.require<Heightfield>("height");
    auto pts = std::make_shared<Points>();
    const auto n = ctx.param<std::int64_t>("count");
    const auto lo = ctx.domain().min_corner(), size = ctx.domain().size();
    for (std::int64_t j = 0; j < n; ++j)
      for (std::int64_t i = 0; i < n; ++i) {
        const double x = lo.x + size.x * (i + 0.5) / n, y = lo.y + size.y * (j + 0.5) / n;
        pts->add({x, y, h->sample_world(x, y)});
      }
    ctx.set_output("points", pts);
  });
}

OROGEN_NODE(EdSlow) {
  b.category("test").description("Editor test node that takes a while and honours cancellation.");
  b.input("in", PortType::Heightfield).description("Input");
  b.output("out", PortType::Heightfield).description("The input, unchanged");
  b.param_int("milliseconds", 2000).range(0, 60000).unit(Unit::Millisecond).description("How long it works");
  b.execute([](ExecContext& ctx) {
    const auto ms = ctx.param<std::int64_t>("milliseconds");
    for (std::int64_t t = 0; t < ms; t += 5) {
      ctx.check_cancelled();
      ctx.progress(static_cast<double>(t) / static_cast<double>(ms));
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ctx.set_output("out", ctx.require<Heightfield>("in"));
  });
}

}  // namespace orogen
