// Requested outputs: the evaluator tells a node which of its outputs anything uses (ExecContext::
// output_requested), the node skips the others, and neither cache hands out a result that lacks an output
// needed now. TestTriple records what it was asked for on every run, so the tests observe what was computed;
// the hydrology nodes that skip work must give the same bytes for what they do compute.
#include <algorithm>
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "evaluator/disk_cache.h"
#include "evaluator/evaluator.h"
#include "evaluator/run_node.h"
#include "graph/exec_context.h"
#include "graph/registry.h"
#include "graph/report.h"
#include "support/depression_terrain.h"
#include "support/eval_results.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

std::mutex g_mutex;
std::vector<std::vector<bool>> g_asked;  // per run of TestTriple: which of its outputs were requested

void reset() {
  std::lock_guard lock(g_mutex);
  g_asked.clear();
}
std::vector<std::vector<bool>> asked() {
  std::lock_guard lock(g_mutex);
  return g_asked;
}

}  // namespace

// Outputs value, 2 value and 3 value, each only when requested.
OROGEN_NODE(TestTriple) {
  b.category("test").description("Three multiples of a value, each computed only when something uses it.");
  b.output("one", PortType::Heightfield).description("value");
  b.output("two", PortType::Heightfield).description("2 value");
  b.output("three", PortType::Heightfield).description("3 value");
  b.param_float("value", 1.0).range(-1e6, 1e6).unit(Unit::Metre).description("The value");
  b.execute([](ExecContext& ctx) {
    const char* names[] = {"one", "two", "three"};
    std::vector<bool> wanted;
    for (const char* n : names) wanted.push_back(ctx.output_requested(n));
    {
      std::lock_guard lock(g_mutex);
      g_asked.push_back(wanted);
    }
    for (int k = 0; k < 3; ++k)
      if (wanted[static_cast<std::size_t>(k)])
        ctx.set_output(names[k], std::make_shared<const Heightfield>(
                                     ctx.domain(), static_cast<float>((k + 1) * ctx.param<double>("value"))));
  });
}

OROGEN_NODE(TestTake) {
  b.category("test").description("Its input plus an offset.");
  b.input("in", PortType::Heightfield).description("Field");
  b.output("out", PortType::Heightfield).description("in + offset");
  b.param_float("offset", 0.0).range(-1e6, 1e6).unit(Unit::Metre).description("Added");
  b.execute([](ExecContext& ctx) {
    auto out = std::make_shared<Heightfield>(*ctx.require<Heightfield>("in"));
    for (float& v : out->data) v += static_cast<float>(ctx.param<double>("offset"));
    ctx.set_output("out", out);
  });
}

// A field and a report, as the nodes the default request asks for their figures (DrainageMetrics, ...).
OROGEN_NODE(TestReporter) {
  b.category("test").description("A field, a second field and a report, recording what it was asked for.");
  b.output("out", PortType::Heightfield).description("1");
  b.output("extra", PortType::Heightfield).description("2");
  b.output("report", PortType::Report).description("A figure");
  b.execute([](ExecContext& ctx) {
    const std::vector<bool> wanted{ctx.output_requested("out"), ctx.output_requested("extra"),
                                   ctx.output_requested("report")};
    {
      std::lock_guard lock(g_mutex);
      g_asked.push_back(wanted);
    }
    if (wanted[0]) ctx.set_output("out", std::make_shared<const Heightfield>(ctx.domain(), 1.0f));
    if (wanted[1]) ctx.set_output("extra", std::make_shared<const Heightfield>(ctx.domain(), 2.0f));
    if (wanted[2]) {
      auto report = std::make_shared<Report>();
      report->json = "{\"figure\": 42}";
      ctx.set_output("report", std::shared_ptr<const Report>(report));
    }
  });
}

// Hilly terrain with closed depressions of every size (tests/support/depression_terrain.h).
OROGEN_NODE(TestHills) {
  b.category("test").description("The routing tests' hilly terrain.");
  b.output("out", PortType::Heightfield).description("Height, metres");
  b.execute([](ExecContext& ctx) {
    auto h = std::make_shared<Heightfield>(ctx.domain());
    h->data = test::depression_terrain(hydrology::FlowGrid::of(ctx.domain()), 3);
    ctx.set_output("out", h);
  });
}

namespace {

const Domain& kDomain = test::kEvalDomain;
const std::vector<bool> kAll{true, true, true};

using test::field;
using test::request;
using test::status;

float value(const EvalResult& r, const Graph& g, const std::string& id, const std::string& port = "out") {
  const auto f = field(r, g, id, port);
  return f ? f->at(3, 3) : -1e9f;
}

// triple -> take1 (from "one").
Graph one_link() {
  Graph g;
  g.add_node("TestTriple", "triple").params["value"] = 5.0;
  g.add_node("TestTake", "take1");
  g.connect({"triple", "one"}, "take1", "in");
  return g;
}

class RequestedOutputs : public ::testing::Test {
 protected:
  void SetUp() override { reset(); }
};

TEST_F(RequestedOutputs, OnlyLinkedOutputsAreComputed) {
  const Graph g = one_link();
  Evaluator ev;
  const auto r = ev.evaluate(g, request({"take1"}));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(value(r, g, "take1"), 5.0f);
  ASSERT_EQ(asked().size(), 1u);
  EXPECT_EQ(asked()[0], (std::vector<bool>{true, false, false}));
  // The partial result is cached, but never given out as the node's complete result.
  const CacheKey key = compute_cache_keys(g, kDomain).at("triple");
  EXPECT_EQ(ev.find_result(key, *g.at("triple").type), nullptr);
  EXPECT_EQ(ev.cache_stats().entries, 2u);
}

TEST_F(RequestedOutputs, ARequestedNodeAndTheDefaultRequestGetEveryOutput) {
  Graph g = one_link();
  Evaluator ev;
  const auto r = ev.evaluate(g, request({"triple"}));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(value(r, g, "triple", "one"), 5.0f);
  EXPECT_EQ(value(r, g, "triple", "two"), 10.0f);
  EXPECT_EQ(value(r, g, "triple", "three"), 15.0f);
  ASSERT_EQ(asked().size(), 1u);
  EXPECT_EQ(asked()[0], kAll);
  // By default the sinks are requested: a node that feeds nothing gives all its outputs.
  g.add_node("TestTriple", "lone").params["value"] = 7.0;
  const auto d = ev.evaluate(g, request({}));
  ASSERT_TRUE(d.ok());
  EXPECT_EQ(value(d, g, "lone", "three"), 21.0f);
  EXPECT_EQ(status(d, "triple"), NodeStatus::Cached);  // the complete result serves the link too
  ASSERT_EQ(asked().size(), 2u);
  EXPECT_EQ(asked()[1], kAll);
}

TEST_F(RequestedOutputs, DefaultRequestAsksANodeThatFeedsOthersForItsReportAndLinksOnly) {
  Graph g;
  g.add_node("TestReporter", "reporter");
  g.add_node("TestTake", "take");
  g.connect({"reporter", "out"}, "take", "in");
  Evaluator ev;
  const auto r = ev.evaluate(g, request({}));
  ASSERT_TRUE(r.ok());
  ASSERT_EQ(asked().size(), 1u);
  EXPECT_EQ(asked()[0], (std::vector<bool>{true, false, true}));
  EXPECT_EQ(value(r, g, "take"), 1.0f);
  const auto report = std::get<ReportPtr>(r.output("reporter", "report", g));
  EXPECT_NE(report->json.find("42"), std::string::npos);
  EXPECT_FALSE(has_value(r.output("reporter", "extra", g)));
  // Asked for by name, it gives everything.
  const auto named = ev.evaluate(g, request({"reporter"}));
  ASSERT_TRUE(named.ok());
  EXPECT_EQ(value(named, g, "reporter", "extra"), 2.0f);
}

TEST_F(RequestedOutputs, LinkingAnotherOutputLaterRecomputesTheUnion) {
  Graph g = one_link();
  Evaluator ev;
  ASSERT_TRUE(ev.evaluate(g, request({"take1"})).ok());
  // As in the editor: a second consumer is linked to another output.
  g.add_node("TestTake", "take3");
  g.connect({"triple", "three"}, "take3", "in");
  const auto r = ev.evaluate(g, request({"take1", "take3"}));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(status(r, "triple"), NodeStatus::Computed);  // the cached result lacks "three": a miss
  EXPECT_EQ(status(r, "take1"), NodeStatus::Cached);
  EXPECT_EQ(value(r, g, "take3"), 15.0f);
  ASSERT_EQ(asked().size(), 2u);
  EXPECT_EQ(asked()[1], (std::vector<bool>{true, false, true}));

  // Only "two" now: the recomputation keeps what the cached entry had, so the entry never shrinks.
  Graph h = g;
  h.add_node("TestTake", "take2");
  h.connect({"triple", "two"}, "take2", "in");
  const auto r2 = ev.evaluate(h, request({"take2"}));
  ASSERT_TRUE(r2.ok());
  EXPECT_EQ(value(r2, h, "take2"), 10.0f);
  ASSERT_EQ(asked().size(), 3u);
  EXPECT_EQ(asked()[2], kAll);
  // Now every link and the node itself are hits.
  const auto r3 = ev.evaluate(h, request({"take1", "take2", "take3", "triple"}));
  ASSERT_TRUE(r3.ok());
  EXPECT_EQ(status(r3, "triple"), NodeStatus::Cached);
  EXPECT_EQ(value(r3, h, "triple", "two"), 10.0f);
  EXPECT_EQ(asked().size(), 3u);
  const CacheKey key = compute_cache_keys(h, kDomain).at("triple");
  EXPECT_NE(ev.find_result(key, *h.at("triple").type), nullptr);
}

TEST_F(RequestedOutputs, NodesWithEqualKeysShareOneRunForTheUnionOfTheirLinks) {
  Graph g;
  for (const std::string s : {"a", "b"}) g.add_node("TestTriple", "triple_" + s).params["value"] = 2.0;
  g.add_node("TestTake", "take_a");
  g.add_node("TestTake", "take_b");
  g.connect({"triple_a", "one"}, "take_a", "in");
  g.connect({"triple_b", "two"}, "take_b", "in");
  Evaluator ev;
  const auto r = ev.evaluate(g, request({"take_a", "take_b"}));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(value(r, g, "take_a"), 2.0f);
  EXPECT_EQ(value(r, g, "take_b"), 4.0f);
  ASSERT_EQ(asked().size(), 1u);
  EXPECT_EQ(asked()[0], (std::vector<bool>{true, true, false}));
  const bool one_computed =
      (status(r, "triple_a") == NodeStatus::Computed) != (status(r, "triple_b") == NodeStatus::Computed);
  EXPECT_TRUE(one_computed);
}

TEST_F(RequestedOutputs, NodeThatLeavesARequestedOutputUnsetStillFails) {
  // A node that ignores output_requested and sets nothing is caught for the requested output only.
  NodeType t;
  t.name = "TestSetsNothing";
  for (const char* name : {"a", "b"}) {
    PortDecl port;
    port.name = name;
    t.outputs.push_back(port);
  }
  t.execute = [](ExecContext&) {};
  ExecContext ctx(t, "n", kDomain, {}, {});
  ctx.set_requested_outputs({false, true});
  EXPECT_FALSE(ctx.output_requested("a"));
  EXPECT_TRUE(ctx.output_requested("b"));
  EXPECT_THROW(ctx.output_requested("c"), std::logic_error);
  ExecContext all(t, "n", kDomain, {}, {});
  EXPECT_TRUE(all.output_requested("a") && all.output_requested("b"));  // unset: every output requested
  EXPECT_THROW(run_node_for_outputs({"one", "four"}, "TestTriple", kDomain), std::logic_error);
}

TEST_F(RequestedOutputs, PersistentCacheStoresPartialResultsMarkedAndNeverAsComplete) {
  const auto dir = test::scratch_dir("requested-outputs-disk");
  EvaluatorOptions options;
  options.cache_dir = dir;
  const Graph g = one_link();
  const CacheKey key = compute_cache_keys(g, kDomain).at("triple");
  {
    Evaluator ev(options);
    ASSERT_TRUE(ev.evaluate(g, request({"take1"})).ok());
  }
  // On disk the unrequested outputs are stored unset.
  {
    const auto loaded = DiskCache(dir).load(key);
    ASSERT_TRUE(loaded.result);
    ASSERT_EQ(loaded.result->outputs.size(), 3u);
    EXPECT_TRUE(has_value(loaded.result->outputs[0]));
    EXPECT_FALSE(has_value(loaded.result->outputs[1]));
    EXPECT_FALSE(has_value(loaded.result->outputs[2]));
  }
  // Another process asking for the complete result gets nothing, and the entry is not treated as damaged.
  {
    Evaluator ev(options);
    EXPECT_EQ(ev.find_result(key, *g.at("triple").type), nullptr);
    EXPECT_EQ(ev.cache_stats().disk_rejected, 0u);
    EXPECT_TRUE(std::filesystem::exists(DiskCache(dir).path_of(key)));
  }
  // A new consumer of the same output is served from the partial entry.
  {
    Graph h = g;
    h.add_node("TestTake", "take1b").params["offset"] = 1.0;
    h.connect({"triple", "one"}, "take1b", "in");
    Evaluator ev(options);
    const auto r = ev.evaluate(h, request({"take1b"}));
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(status(r, "triple"), NodeStatus::Cached);
    EXPECT_EQ(ev.cache_stats().disk_hits, 1u);
    EXPECT_EQ(value(r, h, "take1b"), 6.0f);
    EXPECT_EQ(asked().size(), 1u);
  }
  // Requesting the node itself recomputes it; the complete result replaces the partial one on disk.
  {
    Evaluator ev(options);
    const auto r = ev.evaluate(g, request({"triple"}));
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(status(r, "triple"), NodeStatus::Computed);
    EXPECT_EQ(ev.cache_stats().disk_rejected, 0u);
    EXPECT_EQ(value(r, g, "triple", "three"), 15.0f);
    ASSERT_EQ(asked().size(), 2u);
    EXPECT_EQ(asked()[1], kAll);
  }
  {
    Evaluator ev(options);
    const auto r = ev.evaluate(g, request({"triple"}));
    ASSERT_TRUE(r.ok());
    EXPECT_EQ(status(r, "triple"), NodeStatus::Cached);
    EXPECT_EQ(ev.cache_stats().disk_hits, 1u);
    EXPECT_EQ(value(r, g, "triple", "two"), 10.0f);
    EXPECT_NE(ev.find_result(key, *g.at("triple").type), nullptr);
    EXPECT_EQ(asked().size(), 2u);
  }
}

// ---- The hydrology nodes that skip unrequested outputs ----------------------------------------------------

const Domain kTerrain = Domain::from_extent({0, 0}, {1270, 1270}, {128, 128});  // 10 m

HeightfieldPtr hills() {
  auto h = std::make_shared<Heightfield>(kTerrain);
  h->data = test::depression_terrain(hydrology::FlowGrid::of(kTerrain), 3);
  return h;
}

// Every subset of `type`'s outputs (but the empty one): the requested outputs are set and byte-identical to a
// run with all of them. `skipped` lists groups of outputs whose work the node skips (a group is computed
// together): when no output of a group is requested, the whole group stays unset (so the skipping is real).
void expect_subsets_match(const std::string& type, const std::map<std::string, ParamValue>& params,
                          const std::vector<std::vector<std::string>>& skipped) {
  const auto in = hills();
  const NodeType& t = *NodeRegistry::instance().find(type);
  const NodeRun full = run_node(type, kTerrain, params, {{"in", PortValue(in)}});
  const std::size_t n = t.outputs.size();
  for (unsigned mask = 1; mask < (1u << n); ++mask) {
    std::vector<std::string> names;
    for (std::size_t i = 0; i < n; ++i)
      if (mask >> i & 1) names.push_back(t.outputs[i].name);
    const NodeRun part = run_node_for_outputs(names, type, kTerrain, params, {{"in", PortValue(in)}});
    for (std::size_t i = 0; i < n; ++i) {
      SCOPED_TRACE(type + " mask " + std::to_string(mask) + " output " + t.outputs[i].name);
      if (!(mask >> i & 1)) continue;
      ASSERT_TRUE(has_value(part.outputs[i]));
      if (t.outputs[i].type == PortType::Report)
        EXPECT_EQ(part.get<Report>(i)->json, full.get<Report>(i)->json);
      else
        EXPECT_EQ(part.get<Heightfield>(i)->data, full.get<Heightfield>(i)->data);
    }
    for (const auto& group : skipped) {
      const bool wanted = std::any_of(group.begin(), group.end(), [&](const std::string& name) {
        return std::find(names.begin(), names.end(), name) != names.end();
      });
      if (wanted) continue;
      for (const auto& name : group)
        EXPECT_FALSE(has_value(part.outputs[static_cast<std::size_t>(t.output_index(name))]))
            << type << " mask " << mask << " computed " << name;
    }
  }
}

TEST(RequestedOutputsNodes, FillDepressionsSkipsItsLakeMaps) {
  for (const std::string mode : {"fill", "carve"})
    for (const std::string flats : {"epsilon", "flat"})
      for (const double max_depth : {0.0, 3.0})
        expect_subsets_match("FillDepressions", {{"mode", mode}, {"flats", flats}, {"max_depth", max_depth}},
                             {{"water_depth", "lake_id"}});
}

TEST(RequestedOutputsNodes, LakesSkipsItsMaps) {
  expect_subsets_match("Lakes", {{"min_depth", 0.5}}, {{"water_depth", "lake_id"}});
}

TEST(RequestedOutputsNodes, FlowAccumulationSkipsFlowAndWetness) {
  for (const std::string method : {"d8", "dinf", "mfd"})
    for (const bool fill : {true, false})
      expect_subsets_match("FlowAccumulation", {{"method", method}, {"fill", fill}}, {{"flow"}, {"wetness"}});
}

TEST(RequestedOutputsNodes, FlowDirectionSkipsUnusedMaps) {
  for (const std::string method : {"d8", "mfd"})
    expect_subsets_match("FlowDirection", {{"method", method}}, {{"out"}, {"dx", "dy"}, {"gradient"}});
}

TEST(RequestedOutputsNodes, HydraulicErosionSkipsItsChangeAndFlowMaps) {
  // 128^2 at 10 m: about 33k droplets.
  expect_subsets_match("HydraulicErosion", {}, {{"erosion", "deposition"}, {"flow"}});
}

TEST(RequestedOutputsNodes, FillDepressionsInAGraphComputesLakeMapsOnlyOnceLinked) {
  reset();
  const auto dir = test::scratch_dir("requested-outputs-fill");
  EvaluatorOptions options;
  options.cache_dir = dir;
  Graph g;
  g.add_node("TestHills", "hills");
  g.add_node("FillDepressions", "fill");
  g.add_node("TestTake", "use_out");
  g.connect({"hills", "out"}, "fill", "in");
  g.connect({"fill", "out"}, "use_out", "in");
  const NodeRun full = run_node("FillDepressions", kTerrain, {}, {{"in", PortValue(hills())}});
  const auto& ids = full.get<Heightfield>(2)->data;
  ASSERT_GT(*std::max_element(ids.begin(), ids.end()), 10.0f) << "the terrain has lakes";
  Evaluator ev(options);
  const auto r = ev.evaluate(g, request({"use_out"}, kTerrain));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(field(r, g, "use_out")->data, full.get<Heightfield>(0)->data);
  // What was computed, as the persistent cache holds it: the filled height only.
  const CacheKey key = compute_cache_keys(g, kTerrain).at("fill");
  const auto stored = DiskCache(dir).load(key);
  ASSERT_TRUE(stored.result);
  EXPECT_TRUE(has_value(stored.result->outputs[0]));
  EXPECT_FALSE(has_value(stored.result->outputs[1]));
  EXPECT_FALSE(has_value(stored.result->outputs[2]));

  g.add_node("TestTake", "use_depth");
  g.connect({"fill", "water_depth"}, "use_depth", "in");
  const auto r2 = ev.evaluate(g, request({"use_out", "use_depth"}, kTerrain));
  ASSERT_TRUE(r2.ok());
  EXPECT_EQ(status(r2, "fill"), NodeStatus::Computed);
  EXPECT_EQ(field(r2, g, "use_depth")->data, full.get<Heightfield>(1)->data);
  const auto whole = ev.evaluate(g, request({"fill"}, kTerrain));
  ASSERT_TRUE(whole.ok());
  for (const std::string port : {"out", "water_depth", "lake_id"})
    EXPECT_EQ(field(whole, g, "fill", port)->data,
              full.get<Heightfield>(static_cast<std::size_t>(g.at("fill").type->output_index(port)))->data)
        << port;
}

}  // namespace
}  // namespace orogen
