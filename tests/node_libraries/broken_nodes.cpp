// Deliberately broken node types, each failing one contract `orogen test-node` must catch
// (tests/test_node_library.cpp). Each is otherwise a well-declared node, so only its own contract fails.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include <tbb/task_arena.h>

#include <orogen/node.h>

using namespace orogen;

// Declares domain_independent, which leaves the domain out of its cache key, yet its output follows the
// domain: a result computed for one domain would be served from the cache for another.
OROGEN_NODE(BrokenDomainBlind) {
  b.category("test").description("Broken on purpose: a ramp along x, but declared domain_independent.");
  b.reach_pointwise();
  b.domain_independent();
  b.output("out", PortType::Heightfield).description("x of each sample, metres");
  b.param_float("slope", 1.0)
      .range(-10.0, 10.0)
      .unit(Unit::MetrePerMetre)
      .description("Metres of height per metre along x");
  b.execute([](ExecContext& ctx) {
    auto h = std::make_shared<Heightfield>(ctx.domain());
    const double k = ctx.param<double>("slope");
    for (int j = 0; j < h->domain.height(); ++j)
      for (int i = 0; i < h->domain.width(); ++i) h->at(i, j) = static_cast<float>(k * h->domain.x(i));
    ctx.set_output("out", h);
  });
}

// Averages 5 samples along x (2 on each side) but declares a reach of 1 sample: a tile's border is wrong.
OROGEN_NODE(BrokenNarrowReach) {
  b.category("test").description("Broken on purpose: a 5-sample box filter along x declaring a 1-sample reach.");
  b.reach_local(0.0, 1);
  b.input("in", PortType::Heightfield).description("Heights, metres");
  b.output("out", PortType::Heightfield).description("Heights, metres");
  b.param_float("weight", 1.0).range(0.0, 1.0).unit(Unit::Unitless).description("Unitless blend towards the average");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const double w = ctx.param<double>("weight");
    auto out = std::make_shared<Heightfield>(in->domain);
    const int width = in->domain.width();
    for (int j = 0; j < in->domain.height(); ++j)
      for (int i = 0; i < width; ++i) {
        double sum = 0.0;
        for (int k = -2; k <= 2; ++k) sum += in->at(std::clamp(i + k, 0, width - 1), j);
        out->at(i, j) = static_cast<float>((1.0 - w) * in->at(i, j) + w * sum / 5.0);
      }
    ctx.set_output("out", out);
  });
}

// Subtracts the mean, summed in float over one chunk per worker thread: the rounding, so the result, depends
// on the thread count.
OROGEN_NODE(BrokenThreadSplit) {
  b.category("test").description("Broken on purpose: subtracts the mean, summed in one chunk per thread.");
  b.reach_global();
  b.distribution(Distribution::Reduction);  // a global reach must say how it spreads over MPI ranks
  b.input("in", PortType::Heightfield).description("Heights, metres");
  b.output("out", PortType::Heightfield).description("Heights minus their mean, metres");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const auto n = in->data.size();
    const auto chunks = static_cast<std::size_t>(std::max(1, tbb::this_task_arena::max_concurrency()));
    float total = 0.0f;
    for (std::size_t c = 0; c < chunks; ++c) {
      float partial = 0.0f;
      for (std::size_t k = c * n / chunks; k < (c + 1) * n / chunks; ++k) partial += in->data[k];
      total += partial;
    }
    auto out = std::make_shared<Heightfield>(in->domain);
    for (std::size_t k = 0; k < n; ++k) out->data[k] = in->data[k] - total / static_cast<float>(n);
    ctx.set_output("out", out);
  });
}

// Divides by a parameter whose range includes 0: at that end every finite height becomes an infinity (and 0
// becomes NaN). It should refuse 0 with a NodeError naming the parameter, or start its range above 0.
OROGEN_NODE(BrokenExtremeDivide) {
  b.category("test").description("Broken on purpose: heights divided by a factor whose range includes 0.");
  b.reach_pointwise();
  b.input("in", PortType::Heightfield).description("Heights, metres");
  b.output("out", PortType::Heightfield).description("Heights divided by the factor, metres");
  b.param_float("divisor", 1.0).range(0.0, 100.0).unit(Unit::Factor).description("What the heights are divided by");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const double divisor = ctx.param<double>("divisor");
    auto out = std::make_shared<Heightfield>(in->domain);
    for (std::size_t k = 0; k < in->data.size(); ++k) out->data[k] = static_cast<float>(in->data[k] / divisor);
    ctx.set_output("out", out);
  });
}

// Works in steps that never poll the cancel: at its largest step count it runs for minutes, and `orogen
// test-node` must still print its table (the run is left behind) and exit.
OROGEN_NODE(BrokenIgnoresCancel) {
  b.category("test").description("Broken on purpose: a slow loop that never calls ctx.check_cancelled().");
  b.reach_pointwise();
  b.input("in", PortType::Heightfield).description("Heights, metres");
  b.output("out", PortType::Heightfield).description("The same heights, metres");
  b.param_int("steps", 1).range(1, 1000000).unit(Unit::Count).description("Steps of 1 ms of (pretended) work");
  b.execute([](ExecContext& ctx) {
    const auto steps = ctx.param<std::int64_t>("steps");
    for (std::int64_t k = 0; k < steps; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ctx.set_output("out", ctx.require<Heightfield>("in"));
  });
}
