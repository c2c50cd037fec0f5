// Every registered node at the extremes of every parameter's range, on tiny, huge-coordinate and non-square
// domains, with non-finite inputs: no crash, no sanitizer report, and either a finite result, a NodeError with
// a message, or a prompt return after a cancel. Generated from the registry, so a new node type is covered
// without touching this file.
//
// The checks are the extremes contract of testing/contracts.h (the one `orogen test-node` and the testing kit
// run); here with the longer budgets of a registry-wide test, the bound of tests/test_cancellation.cpp, and
// values of every port type a registered node makes (points, meshes, scenes ...) as inputs.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <thread>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/node_type.h"
#include "graph/registry.h"
#include "support/registered_types.h"
#include "support/sample_values.h"
#include "support/sanitizers.h"
#include "support/test_paths.h"
#include "testing/contracts.h"

namespace orogen {
namespace {

#ifdef OROGEN_TEST_ASAN
constexpr double kCancelBound = 5.0;  // seconds from the cancel to the return, under AddressSanitizer
#else
constexpr double kCancelBound = 1.0;  // seconds from the cancel to the return
#endif

class NodeExtremes : public ::testing::TestWithParam<std::string> {};

TEST_P(NodeExtremes, ResultOrClearErrorEverywhere) {
  const NodeType* type = NodeRegistry::instance().find(GetParam());
  ASSERT_NE(type, nullptr);
  contracts::ExtremesOptions o;
  o.run_seconds = 1.0;
  o.cancel_bound = kCancelBound;
  // Simulations at their largest settings are each cut at run_seconds; the sweep still covers every domain
  // and input kind first.
  o.budget_seconds = 20.0;
  o.output.output_dir = test::scratch_dir("extremes-" + type->name);
  o.inputs = [&](const Domain& d) {
    auto smooth = std::make_shared<Heightfield>(d);
    for (int j = 0; j < d.height(); ++j)
      for (int i = 0; i < d.width(); ++i)
        smooth->at(i, j) = static_cast<float>(50.0 + 40.0 * std::sin(0.7 * i + 0.3 * j));
    return test::sample_values(smooth, o.output);
  };
  const auto r = contracts::check_extremes(*type, o);
  for (const auto& f : r.failures) ADD_FAILURE() << f;
  if (r.status == contracts::Status::Skipped) GTEST_SKIP() << r.note;
}

INSTANTIATE_TEST_SUITE_P(Registry, NodeExtremes, testing::ValuesIn(test::registered_type_names()),
                         test::type_test_name);

// The contract can fail: a node that divides by a parameter whose range includes 0, one that throws a
// std::runtime_error at an extreme, and one that ignores the cancel.
NodeType fake(const std::string& name, std::function<void(ExecContext&)> run) {
  NodeType t;
  t.name = name;
  t.category = "test";
  t.description = "A node broken on purpose for the extremes contract";
  NodeBuilder b(t);
  b.reach_pointwise();
  b.input("in", PortType::Heightfield).description("Heights, metres");
  b.output("out", PortType::Heightfield).description("Heights, metres");
  b.param_float("scale", 1.0).range(0.0, 10.0).unit(Unit::Metre).description("Metres");
  b.execute(std::move(run));
  return t;
}

bool any_contains(const std::vector<std::string>& failures, const std::string& part) {
  for (const auto& f : failures)
    if (f.find(part) != std::string::npos) return true;
  return false;
}

TEST(ExtremesContract, CatchesNonFiniteResultsForeignExceptionsAndIgnoredCancels) {
  auto divide = fake("ExtremesDivides", [](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    auto out = std::make_shared<Heightfield>(in->domain);
    for (std::size_t k = 0; k < in->data.size(); ++k)
      out->data[k] = static_cast<float>(in->data[k] / ctx.param<double>("scale"));
    ctx.set_output("out", out);
  });
  auto foreign = fake("ExtremesThrows", [](ExecContext& ctx) {
    if (ctx.param<double>("scale") > 5.0) throw std::runtime_error("scale too large");
    ctx.set_output("out", ctx.require<Heightfield>("in"));
  });
  auto refuses = fake("ExtremesRefuses", [](ExecContext& ctx) {
    if (ctx.param<double>("scale") == 0.0) throw NodeError("scale must be positive");
    ctx.set_output("out", ctx.require<Heightfield>("in"));
  });
  auto stubborn = fake("ExtremesIgnoresCancel", [](ExecContext& ctx) {
    if (ctx.param<double>("scale") == 10.0) std::this_thread::sleep_for(std::chrono::milliseconds(400));
    ctx.set_output("out", ctx.require<Heightfield>("in"));
  });
  for (NodeType* t : {&divide, &foreign, &refuses, &stubborn}) NodeRegistry::instance().add(*t);
  contracts::ExtremesOptions o;
  o.run_seconds = 0.05;
  o.cancel_bound = 0.1;

  const auto d = contracts::check_extremes(divide, o);
  EXPECT_EQ(d.status, contracts::Status::Failed);
  EXPECT_TRUE(any_contains(d.failures, "scale = min (0)")) << testing::PrintToString(d.failures);
  EXPECT_TRUE(any_contains(d.failures, "although every input was finite")) << testing::PrintToString(d.failures);

  const auto f = contracts::check_extremes(foreign, o);
  EXPECT_EQ(f.status, contracts::Status::Failed);
  EXPECT_TRUE(any_contains(f.failures, "threw std::runtime_error (\"scale too large\"), not a NodeError"))
      << testing::PrintToString(f.failures);
  EXPECT_FALSE(any_contains(f.failures, "scale = min")) << "only the failing end is named";

  const auto ok = contracts::check_extremes(refuses, o);
  EXPECT_EQ(ok.status, contracts::Status::Passed) << testing::PrintToString(ok.failures);
  EXPECT_NE(ok.note.find("errors"), std::string::npos) << ok.note;

  const auto s = contracts::check_extremes(stubborn, o);
  EXPECT_EQ(s.status, contracts::Status::Failed);
  EXPECT_TRUE(any_contains(s.failures, "after it was cancelled")) << testing::PrintToString(s.failures);
}

// A node that ignores the cancel altogether is left running, the sweep stops (so the table is still printed),
// and the run is counted until it returns.
TEST(ExtremesContract, ANodeIgnoringTheCancelIsLeftRunningAndTheSweepStops) {
  auto hangs = fake("ExtremesHangs", [](ExecContext& ctx) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    ctx.set_output("out", ctx.require<Heightfield>("in"));
  });
  NodeRegistry::instance().add(hangs);
  contracts::ExtremesOptions o;
  o.run_seconds = 0.05;
  o.cancel_bound = 0.1;
  const auto start = std::chrono::steady_clock::now();
  const auto r = contracts::check_extremes(hangs, o);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.2)
      << "the sweep did not wait for the node";
  EXPECT_EQ(r.status, contracts::Status::Failed);
  ASSERT_EQ(r.failures.size(), 1u) << testing::PrintToString(r.failures);
  EXPECT_NE(r.failures[0].find("defaults: still running 0.4 s after it was cancelled"), std::string::npos)
      << r.failures[0];
  EXPECT_EQ(contracts::runs_left_running(), 1);
  for (int k = 0; k < 100 && contracts::runs_left_running() > 0; ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(contracts::runs_left_running(), 0) << "the abandoned run counted itself out when it returned";
}

}  // namespace
}  // namespace orogen
