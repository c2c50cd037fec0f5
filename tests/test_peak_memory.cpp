// The memory estimate behind --max-memory (evaluator/memory_estimate.h) against each node's measured peak, for
// every registered node type (from the registry: a new node type is covered without touching this file). Each
// node runs on small domains with the representative inputs of tests/support/sample_values and its default
// parameters; every heap byte the process holds is counted (tests/support/counting_malloc.h), and the node's
// peak is the most held above what was held before it started (its outputs included, its inputs not). The
// estimate, asked with the real inputs as the evaluator asks just before a node runs, must lie within a factor
// kFactor of that peak, both ways, give or take kFloorBytes (allocations that do not grow with the domain:
// the run's bookkeeping, TBB's tasks, a library's tables).
//
// Skipped under AddressSanitizer, which owns malloc (and whose peak would be its own).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "evaluator/memory_estimate.h"
#include "evaluator/run_node.h"
#include "graph/cost_query.h"
#include "graph/graph.h"
#include "graph/heightfield.h"
#include "graph/registry.h"
#include "nodes/io/heightfield_file.h"
#include "support/registered_types.h"
#include "support/sample_values.h"
#include "support/sanitizers.h"
#include "support/test_paths.h"

#ifndef OROGEN_TEST_ASAN
#include "support/counting_malloc.h"
#endif

namespace orogen {
namespace {

namespace fs = std::filesystem;

constexpr double kFactor = 2.0;
constexpr std::int64_t kFloorBytes = 16 * 1024;

// Node types whose estimate is not held to the bound, each with the reason. Empty is the goal.
const std::map<std::string, std::string> kExceptions = {};

// A terrain with relief at every scale the nodes look at: a bowl, ridges and a ripple.
HeightfieldPtr terrain(const Domain& d) {
  auto h = std::make_shared<Heightfield>(d);
  const glm::dvec2 c = d.min_corner() + 0.5 * d.size();
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) {
      const glm::dvec2 q = (d.position(i, j) - c) / d.size();
      h->at(i, j) = static_cast<float>(200.0 * glm::dot(q, q) + 40.0 * std::sin(9.0 * q.x) * std::cos(7.0 * q.y) +
                                       5.0 * std::sin(0.7 * i + 0.3 * j));
    }
  return h;
}

struct Measured {
  std::int64_t peak = 0;
  std::uint64_t estimate = 0;
  std::string error;  // the node failed with this message
};

#ifndef OROGEN_TEST_ASAN
Measured measure(const NodeType& type, const Domain& d, const std::map<std::string, ParamValue>& params,
                 const std::map<std::string, PortValue>& inputs, const OutputPolicy& policy,
                 const fs::path& input_dir) {
  Measured m;
  Graph g;
  Node& n = g.add_node(type.name, "n");
  for (const auto& [name, value] : params) n.params[name] = value;
  const std::vector<ParamValue> effective = g.effective_params(n);
  std::vector<PortValue> by_index(type.inputs.size());
  for (std::size_t k = 0; k < type.inputs.size(); ++k)
    if (auto it = inputs.find(type.inputs[k].name); it != inputs.end()) by_index[k] = it->second;
  m.estimate = estimate_node_bytes(CostQuery{type, d, ParamView(type, effective), &by_index, input_dir, {}});
  try {
    (void)run_node(type.name, d, params, inputs, policy);  // warm: one-time tables, TBB's arena
  } catch (const std::exception& e) {
    m.error = e.what();
    return m;
  }
  {
    const std::int64_t before = test::counting_malloc::current_bytes();
    test::counting_malloc::reset_peak();
    NodeRun run = run_node(type.name, d, params, inputs, policy);
    m.peak = test::counting_malloc::peak_bytes() - before;
  }
  return m;
}
#endif

// Parameters a node needs to do its real work at all (a file to read), per type.
std::map<std::string, ParamValue> params_for(const NodeType& type, const Domain& d, const fs::path& dir) {
  if (type.name != "ReadHeightfield") return {};
  const fs::path png = dir / ("read" + std::to_string(d.width()) + ".png");
  if (!fs::exists(png)) {
    HeightfieldWriteOptions o;
    o.format = HeightFormat::Png16;
    o.range = HeightRange{-100.0, 400.0};
    write_heightfield_file(*terrain(d), png, o);
  }
  return {{"path", png.string()}};
}

class EveryNodesEstimate : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryNodesEstimate, IsWithinAFactorOfTwoOfItsMeasuredPeak) {
#ifdef OROGEN_TEST_ASAN
  GTEST_SKIP() << "AddressSanitizer owns malloc: the counting allocator cannot be installed";
#else
  const NodeType* type = NodeRegistry::instance().find(GetParam());
  ASSERT_NE(type, nullptr);
  const fs::path dir = test::scratch_dir("peak-" + type->name);
  OutputPolicy policy;
  policy.output_dir = dir / "out";
  for (const int side : {64, 128}) {
    const Domain d = Domain::from_extent({0, 0}, {10.0 * side, 10.0 * side}, {side, side});
    const auto values = test::sample_values(terrain(d), policy);
    std::map<std::string, PortValue> inputs;
    for (const auto& in : type->inputs) {
      if (auto it = values.find(in.type); it != values.end())
        inputs[in.name] = it->second;
      else if (!in.optional)
        GTEST_SKIP() << "no producer of a " << in.name << " input yet";
    }
    // Inputs of a particular kind, not just of the port's type: monthly channels for Temperature.
    const std::map<std::string, std::map<std::string, std::string> > producers = {
        {"Temperature", {{"illumination", "SunIllumination"}}}};
    if (auto it = producers.find(type->name); it != producers.end())
      for (const auto& [port, producer] : it->second)
        inputs[port] = run_node(producer, d, {}, {{"in", PortValue(terrain(d))}}).outputs.at(0);
    const Measured m = measure(*type, d, params_for(*type, d, dir), inputs, policy, dir);
    ASSERT_TRUE(m.error.empty()) << type->name << " failed at " << side << "^2 with its defaults: " << m.error;
    const double ratio = static_cast<double>(m.estimate) / static_cast<double>(std::max<std::int64_t>(m.peak, 1));
    std::cout << "peak " << type->name << " " << side << "^2: measured " << m.peak << " B, estimate " << m.estimate
              << " B, ratio " << ratio << "\n";
    if (auto it = kExceptions.find(type->name); it != kExceptions.end()) {
      std::cout << "  not held to the bound: " << it->second << "\n";
      continue;
    }
    const auto estimate = static_cast<double>(m.estimate);
    const auto peak = static_cast<double>(m.peak);
    EXPECT_GE(estimate, peak / kFactor - kFloorBytes)
        << type->name << " at " << side << "^2: the estimate is below half the measured peak";
    EXPECT_LE(estimate, peak * kFactor + kFloorBytes)
        << type->name << " at " << side << "^2: the estimate is above twice the measured peak";
  }
#endif
}

INSTANTIATE_TEST_SUITE_P(Registry, EveryNodesEstimate, testing::ValuesIn(test::registered_type_names()),
                         test::type_test_name);

// A 16384^2 image that is a few hundred kilobytes on disk (constant 8-bit grey) read onto 257^2: streamed, the
// read holds the output and a band of rows (about 1.3 MB), where reading it whole held 16384^2 doubles (3.7 GB,
// issue #30, 7). The estimate says so before the file is decoded, and every sample is the file's value.
TEST(ReadHeightfieldStreaming, A16384SquareFileOntoA257SquareDomainHoldsABandNotTheImage) {
#ifdef OROGEN_TEST_ASAN
  GTEST_SKIP() << "AddressSanitizer owns malloc: the counting allocator cannot be installed";
#else
  const fs::path dir = test::scratch_dir("peak-read-large");
  const fs::path png = dir / "flat16384.png";
  constexpr int kSide = 16384;
  constexpr unsigned char kGrey = 100;
  {
    OIIO::ImageSpec spec(kSide, kSide, 1, OIIO::TypeDesc::UINT8);
    auto out = OIIO::ImageOutput::create(png.string());
    ASSERT_TRUE(out && out->open(png.string(), spec));
    const std::vector<unsigned char> row(kSide, kGrey);
    for (int y = 0; y < kSide; ++y) ASSERT_TRUE(out->write_scanline(y, 0, OIIO::TypeDesc::UINT8, row.data()));
    out->close();
  }
  EXPECT_LT(fs::file_size(png), 1u << 20) << "the case is a file small on disk";
  const NodeType& type = *NodeRegistry::instance().find("ReadHeightfield");
  const Domain d = Domain::from_extent({0, 0}, {2560, 2560}, {257, 257});
  const std::map<std::string, ParamValue> params = {{"path", png.string()}, {"use_file_mapping", false}};
  const Measured m = measure(type, d, params, {}, {}, dir);
  ASSERT_TRUE(m.error.empty()) << m.error;
  std::cout << "16384^2 onto 257^2: measured " << m.peak << " B, estimate " << m.estimate << " B\n";
  EXPECT_LT(m.peak, 8 << 20) << "more than the output and a band of rows";
  EXPECT_GE(static_cast<double>(m.estimate), static_cast<double>(m.peak) / kFactor);
  EXPECT_LE(static_cast<double>(m.estimate), static_cast<double>(m.peak) * kFactor);
  const auto run = run_node("ReadHeightfield", d, params);
  const float expected = static_cast<float>(0.0 + kGrey / 255.0 * 1000.0);  // height_min 0, height_max 1000
  const auto& h = *run.get<Heightfield>();
  std::size_t wrong = 0;
  for (const float v : h.data) wrong += v != expected;
  EXPECT_EQ(wrong, 0u);
#endif
}

#ifndef OROGEN_TEST_ASAN
// The counter sees what it is meant to: a vector of 1 MB is a peak of about 1 MB, whoever frees it.
TEST(CountingMalloc, SeesAllocationsThroughNewAndMalloc) {
  const std::int64_t before = test::counting_malloc::current_bytes();
  test::counting_malloc::reset_peak();
  { std::vector<float> v(1 << 18, 1.0f); }
  void* p = std::malloc(1 << 20);
  static_cast<char*>(p)[0] = 1;
  std::free(p);
  const std::int64_t peak = test::counting_malloc::peak_bytes() - before;
  EXPECT_GE(peak, 1 << 20);
  EXPECT_LT(peak, (1 << 20) + (1 << 16)) << "the vector was freed before the block was taken";
  EXPECT_EQ(test::counting_malloc::current_bytes(), before);
}
#endif

}  // namespace
}  // namespace orogen
