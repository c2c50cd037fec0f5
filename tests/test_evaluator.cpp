// Evaluator: laziness, cache hits and misses, persistence, parallel determinism, cancellation, error
// isolation, events, writers. Uses its own small node types (names starting with "Test") that count their
// executions, so the tests observe what ran rather than how long it took.
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <fstream>
#include <mutex>
#include <numbers>
#include <thread>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "evaluator/disk_cache.h"
#include "evaluator/domain_crop.h"
#include "evaluator/evaluator.h"
#include "evaluator/run_node.h"
#include "graph/atomic_file.h"
#include "graph/exec_context.h"
#include "graph/image.h"
#include "graph/points.h"
#include "graph/registry.h"
#include "nodes/common/cancellable_rows.h"
#include "support/eval_results.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

std::atomic<int> g_source_runs{0}, g_add_runs{0}, g_slow_runs{0}, g_fail_runs{0}, g_writer_runs{0}, g_ripple_runs{0},
    g_delay_runs{0};

// TestSlow: signals that it started, then waits until released or cancelled.
std::mutex g_slow_mutex;
std::condition_variable g_slow_cv;
bool g_slow_started = false;
std::atomic<bool> g_slow_release{false};

// TestSource's latest output, to see when the evaluator lets go of it.
std::mutex g_probe_mutex;
std::weak_ptr<const Heightfield> g_last_source_output;

// TestRendezvous: counts the nodes that arrived and those that met all the others.
std::mutex g_rendezvous_mutex;
std::condition_variable g_rendezvous_cv;
int g_rendezvous_arrived = 0;
std::atomic<int> g_rendezvous_met{0};

void reset_counters() {
  for (auto* c : {&g_source_runs, &g_add_runs, &g_slow_runs, &g_fail_runs, &g_writer_runs, &g_ripple_runs,
                  &g_delay_runs, &g_rendezvous_met})
    c->store(0);
  {
    std::lock_guard lock(g_slow_mutex);
    g_slow_started = false;
    g_slow_release = false;
  }
  std::lock_guard lock(g_rendezvous_mutex);
  g_rendezvous_arrived = 0;
}

}  // namespace

OROGEN_NODE(TestSource) {
  b.category("test").description("A flat field that counts its executions.");
  b.output("out", PortType::Heightfield).description("The field");
  b.param_float("value", 1.0).range(-1e6, 1e6).unit(Unit::Metre).description("Value of every sample");
  b.execute([](ExecContext& ctx) {
    ++g_source_runs;
    auto out = std::make_shared<const Heightfield>(ctx.domain(), static_cast<float>(ctx.param<double>("value")));
    {
      std::lock_guard lock(g_probe_mutex);
      g_last_source_output = out;
    }
    ctx.set_output("out", out);
  });
}

OROGEN_NODE(TestAdd) {
  b.category("test").description("a + b + offset, counting its executions.");
  b.input("a", PortType::Heightfield).description("First field");
  b.input("b", PortType::Heightfield).optional().description("Second field (0 when unconnected)");
  b.output("out", PortType::Heightfield).description("The sum");
  b.param_float("offset", 0.0).range(-1e6, 1e6).unit(Unit::Metre).description("Added to every sample");
  b.execute([](ExecContext& ctx) {
    ++g_add_runs;
    const auto a = ctx.require<Heightfield>("a");
    const auto bb = ctx.input<Heightfield>("b");
    auto out = std::make_shared<Heightfield>(*a);
    const float offset = static_cast<float>(ctx.param<double>("offset"));
    for (std::size_t k = 0; k < out->data.size(); ++k) out->data[k] += (bb ? bb->data[k] : 0.0f) + offset;
    ctx.set_output("out", out);
  });
}

// Takes at least `milliseconds` (a sleep), then adds 1 to its input: a node whose compute time has a known floor.
OROGEN_NODE(TestDelay) {
  b.category("test").description("Waits, then adds 1 to its input, counting its executions.");
  b.input("in", PortType::Heightfield).description("The field");
  b.output("out", PortType::Heightfield).description("The field plus 1");
  b.param_float("milliseconds", 1.0).range(0.0, 1e4).description("How long it waits");
  b.execute([](ExecContext& ctx) {
    ++g_delay_runs;
    std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(ctx.param<double>("milliseconds")));
    auto out = std::make_shared<Heightfield>(*ctx.require<Heightfield>("in"));
    for (auto& v : out->data) v += 1.0f;
    ctx.set_output("out", out);
  });
}

// Real data-parallel math: a rippled field of its input, row-parallel like the real nodes.
OROGEN_NODE(TestRipple) {
  b.category("test").description("sin/cos ripples over the input, row-parallel.");
  b.input("in", PortType::Heightfield).optional().description("Field to ripple (0 when unconnected)");
  b.output("out", PortType::Heightfield).description("The rippled field");
  b.param_float("wavelength", 50.0).range(1e-3, 1e6).unit(Unit::Metre).description("Ripple wavelength");
  b.execute([](ExecContext& ctx) {
    ++g_ripple_runs;
    const auto in = ctx.input<Heightfield>("in");
    const Domain& d = ctx.domain();
    auto out = std::make_shared<Heightfield>(d);
    const double k = 2.0 * std::numbers::pi / ctx.param<double>("wavelength");
    parallel_rows(ctx, d.height(), [&](int j) {
      for (int i = 0; i < d.width(); ++i) {
        const double base = in ? in->at(i, j) : 0.0;
        double v = base;
        for (int t = 1; t <= 8; ++t) v += std::sin(k * t * d.x(i) + base) * std::cos(k * d.y(j) / t) / t;
        out->at(i, j) = static_cast<float>(v);
      }
    });
    ctx.set_output("out", out);
  });
}

OROGEN_NODE(TestSlow) {
  b.category("test").description("Waits until released or cancelled, reporting progress.");
  b.input("in", PortType::Heightfield).optional().description("Passed through");
  b.output("out", PortType::Heightfield).description("The input, or a zero field");
  b.execute([](ExecContext& ctx) {
    ++g_slow_runs;
    {
      std::lock_guard lock(g_slow_mutex);
      g_slow_started = true;
    }
    g_slow_cv.notify_all();
    // Bounded so a broken cancellation fails the test instead of hanging it.
    for (int step = 0; step < 60000 && !g_slow_release; ++step) {
      ctx.check_cancelled();
      ctx.progress(std::min(0.99, step / 1000.0));
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    auto in = ctx.input<Heightfield>("in");
    ctx.set_output("out", in ? in : std::make_shared<const Heightfield>(ctx.domain()));
  });
}

OROGEN_NODE(TestProgress) {
  b.category("test").description("Reports progress over rows and passes its input through.");
  b.input("in", PortType::Heightfield).description("Passed through");
  b.output("out", PortType::Heightfield).description("The input");
  b.execute([](ExecContext& ctx) {
    for (int j = 0; j <= 50; ++j) {
      ctx.progress(j / 50.0);
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ctx.set_output("out", ctx.require<Heightfield>("in"));
  });
}

OROGEN_NODE(TestFail) {
  b.category("test").description("Always fails.");
  b.input("in", PortType::Heightfield).optional().description("Ignored");
  b.output("out", PortType::Heightfield).description("Never set");
  b.param_enum("how", {"node_error", "std_exception", "no_output"}, "node_error").description("How to fail");
  b.execute([](ExecContext& ctx) {
    ++g_fail_runs;
    switch (ctx.enum_index("how")) {
      case 0:
        throw NodeError("deliberate failure");
      case 1:
        throw std::runtime_error("a std::runtime_error");
      default:
        return;  // forgets to set its output
    }
  });
}

OROGEN_NODE(TestWriter) {
  b.category("test").description("Writes the sum of its input's samples to a text file.");
  b.writes_files();
  b.input("in", PortType::Heightfield).description("Field to sum");
  b.param_path("path", "sum.txt").output_file().extensions({".txt"}).description("Text file to write");
  b.execute([](ExecContext& ctx) {
    ++g_writer_runs;
    const auto in = ctx.require<Heightfield>("in");
    double sum = 0.0;
    for (float v : in->data) sum += v;
    const auto path = ctx.output_path("path");
    write_text_atomically(path, std::to_string(sum) + "\n");
    ctx.record_written_file(path);
  });
}

OROGEN_NODE(TestPair) {
  b.category("test").description("Two outputs: the input and its negation.");
  b.input("in", PortType::Heightfield).description("Field");
  b.output("same", PortType::Heightfield).description("The input");
  b.output("negated", PortType::Heightfield).description("Minus the input");
  b.execute([](ExecContext& ctx) {
    auto in = ctx.require<Heightfield>("in");
    auto neg = std::make_shared<Heightfield>(*in);
    for (auto& v : neg->data) v = -v;
    ctx.set_output("same", in);
    ctx.set_output("negated", neg);
  });
}

// Waits until `parties` TestRendezvous nodes are running at the same time: only possible if the evaluator
// runs independent branches concurrently. Gives up after a long safety timeout and records the failure.
OROGEN_NODE(TestRendezvous) {
  b.category("test").description("Waits for the other rendezvous nodes to be running too.");
  b.output("out", PortType::Heightfield).description("A zero field");
  b.param_int("parties", 2).unit(Unit::Count).range(1, 64).description("How many nodes must meet");
  b.param_int("tag", 0).unit(Unit::Count).description("Makes otherwise equal nodes distinct");
  b.execute([](ExecContext& ctx) {
    std::unique_lock lock(g_rendezvous_mutex);
    ++g_rendezvous_arrived;
    g_rendezvous_cv.notify_all();
    const auto parties = ctx.param<std::int64_t>("parties");
    if (g_rendezvous_cv.wait_for(lock, std::chrono::seconds(60), [&] { return g_rendezvous_arrived >= parties; }))
      ++g_rendezvous_met;
    ctx.set_output("out", std::make_shared<const Heightfield>(ctx.domain()));
  });
}

// Checks, while it runs, whether the evaluator still holds TestSource's latest output.
std::atomic<int> g_probe_saw_source_alive{-1};
OROGEN_NODE(TestProbe) {
  b.category("test").description("Records whether TestSource's last output is still alive.");
  b.input("in", PortType::Heightfield).description("Passed through");
  b.output("out", PortType::Heightfield).description("The input");
  b.execute([](ExecContext& ctx) {
    {
      std::lock_guard lock(g_probe_mutex);
      g_probe_saw_source_alive = g_last_source_output.expired() ? 0 : 1;
    }
    ctx.set_output("out", ctx.require<Heightfield>("in"));
  });
}

namespace {

// "s3" and the like (spelled out: GCC 12 warns falsely on "s" + std::to_string(k) at -O3).
std::string numbered(const char* prefix, int k) {
  std::string s(prefix);
  s += std::to_string(k);
  return s;
}

const Domain& kDomain = test::kEvalDomain;

class EvaluatorTest : public ::testing::Test {
 protected:
  void SetUp() override { reset_counters(); }
};

EvaluatorOptions writing_to(const std::filesystem::path& dir) {
  EvaluatorOptions o;
  o.output.output_dir = dir;
  return o;
}

using test::field;
using test::request;
using test::status;

// source -> a -> b, plus an independent source2 -> c.
Graph two_branches() {
  Graph g;
  g.add_node("TestSource", "source").params["value"] = 2.0;
  g.add_node("TestAdd", "a").params["offset"] = 1.0;
  g.add_node("TestAdd", "b").params["offset"] = 10.0;
  g.add_node("TestSource", "source2").params["value"] = 5.0;
  g.add_node("TestAdd", "c");
  g.connect({"source", "out"}, "a", "a");
  g.connect({"a", "out"}, "b", "a");
  g.connect({"source2", "out"}, "c", "a");
  return g;
}

TEST_F(EvaluatorTest, RequestingOneBranchRunsOnlyItsUpstream) {
  const Graph g = two_branches();
  Evaluator ev;
  const auto r = ev.evaluate(g, request({"a"}));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(g_source_runs, 1);
  EXPECT_EQ(g_add_runs, 1);
  EXPECT_EQ(r.nodes.size(), 2u);  // source and a: nothing else was touched
  EXPECT_EQ(status(r, "source"), NodeStatus::Computed);
  EXPECT_EQ(status(r, "a"), NodeStatus::Computed);
  ASSERT_TRUE(field(r, g, "a"));
  EXPECT_EQ(field(r, g, "a")->at(3, 4), 3.0f);
  EXPECT_EQ(r.outputs.size(), 1u);  // only the requested node's outputs are returned
}

TEST_F(EvaluatorTest, ParamEditRecomputesOnlyDownstreamAndUndoIsAFullHit) {
  Graph g = two_branches();
  Evaluator ev;
  ASSERT_TRUE(ev.evaluate(g, request({"b", "c"})).ok());
  EXPECT_EQ(g_source_runs, 2);
  EXPECT_EQ(g_add_runs, 3);

  g.set_param("a", "offset", 4.0);
  auto r = ev.evaluate(g, request({"b", "c"}));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(g_source_runs, 2) << "the source upstream of the edit must come from the cache";
  EXPECT_EQ(g_add_runs, 5) << "a and b recompute, c does not";
  EXPECT_EQ(status(r, "source"), NodeStatus::Cached);
  EXPECT_EQ(status(r, "a"), NodeStatus::Computed);
  EXPECT_EQ(status(r, "b"), NodeStatus::Computed);
  EXPECT_EQ(status(r, "c"), NodeStatus::Cached);
  EXPECT_EQ(r.nodes.count("source2"), 0u) << "upstream of a hit is never touched";
  EXPECT_EQ(field(r, g, "b")->at(0, 0), 2.0f + 4.0f + 10.0f);

  g.set_param("a", "offset", 1.0);  // undo
  r = ev.evaluate(g, request({"b", "c"}));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(g_source_runs, 2);
  EXPECT_EQ(g_add_runs, 5);
  EXPECT_EQ(status(r, "b"), NodeStatus::Cached);
  EXPECT_EQ(status(r, "c"), NodeStatus::Cached);
  EXPECT_EQ(r.nodes.size(), 2u) << "a full hit touches only the requested nodes";
  EXPECT_EQ(field(r, g, "b")->at(0, 0), 2.0f + 1.0f + 10.0f);
}

TEST_F(EvaluatorTest, IdenticalSubgraphsShareOneResult) {
  Graph g;
  for (const std::string suffix : {"1", "2"}) {
    g.add_node("TestSource", "s" + suffix).params["value"] = 3.0;
    g.add_node("TestAdd", "a" + suffix).params["offset"] = 1.5;
    g.connect({"s" + suffix, "out"}, "a" + suffix, "a");
  }
  Evaluator ev;
  const auto r = ev.evaluate(g, request({"a1", "a2"}));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(g_source_runs, 1);
  EXPECT_EQ(g_add_runs, 1);
  EXPECT_EQ(status(r, "a1"), NodeStatus::Computed);
  EXPECT_EQ(status(r, "a2"), NodeStatus::Cached);
  EXPECT_EQ(field(r, g, "a1"), field(r, g, "a2")) << "one shared value, not a copy";
  EXPECT_EQ(ev.cache_stats().entries, 2u);

  // A third copy added later is a hit as well.
  g.add_node("TestSource", "s3").params["value"] = 3.0;
  g.add_node("TestAdd", "a3").params["offset"] = 1.5;
  g.connect({"s3", "out"}, "a3", "a");
  EXPECT_EQ(status(ev.evaluate(g, request({"a3"})), "a3"), NodeStatus::Cached);
  EXPECT_EQ(g_add_runs, 1);
}

TEST_F(EvaluatorTest, DifferentOutputsOfOneNodeAreDifferentInputs) {
  Graph g;
  g.add_node("TestSource", "s").params["value"] = 3.0;
  g.add_node("TestPair", "pair");
  g.add_node("TestAdd", "x");
  g.add_node("TestAdd", "y");
  g.connect({"s", "out"}, "pair", "in");
  g.connect({"pair", "same"}, "x", "a");
  g.connect({"pair", "negated"}, "y", "a");
  Evaluator ev;
  const auto r = ev.evaluate(g, request({"x", "y"}));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(field(r, g, "x")->at(0, 0), 3.0f);
  EXPECT_EQ(field(r, g, "y")->at(0, 0), -3.0f);
  EXPECT_EQ(g_add_runs, 2);
}

TEST_F(EvaluatorTest, MemoryCacheHoldsItsByteBound) {
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {64, 64});
  const std::size_t one = Heightfield(d).byte_size();
  EvaluatorOptions options;
  options.cache_bytes = 3 * one + one / 2;  // room for three results
  Evaluator ev(options);
  Graph g;
  for (int k = 0; k < 8; ++k) g.add_node("TestSource", numbered("s", k)).params["value"] = double(k);
  for (int k = 0; k < 8; ++k) {
    ASSERT_TRUE(ev.evaluate(g, request({numbered("s", k)}, d)).ok());
    const auto stats = ev.cache_stats();
    EXPECT_LE(stats.bytes, options.cache_bytes);
    EXPECT_LE(stats.entries, 3u);
  }
  EXPECT_EQ(ev.cache_stats().evictions, 5u);
  EXPECT_EQ(ev.cache_stats().capacity, options.cache_bytes);
  // The most recent results are hits, the oldest were evicted.
  EXPECT_EQ(status(ev.evaluate(g, request({"s7"}, d)), "s7"), NodeStatus::Cached);
  EXPECT_EQ(status(ev.evaluate(g, request({"s5"}, d)), "s5"), NodeStatus::Cached);
  EXPECT_EQ(g_source_runs, 8);
  EXPECT_EQ(status(ev.evaluate(g, request({"s0"}, d)), "s0"), NodeStatus::Computed);
  EXPECT_EQ(g_source_runs, 9);
  // s5 was used more recently than s6, so s6 made room for s0.
  EXPECT_EQ(status(ev.evaluate(g, request({"s5"}, d)), "s5"), NodeStatus::Cached);
  EXPECT_EQ(status(ev.evaluate(g, request({"s6"}, d)), "s6"), NodeStatus::Computed);
}

TEST_F(EvaluatorTest, ResultLargerThanTheBoundIsReturnedButNotCached) {
  EvaluatorOptions options;
  options.cache_bytes = 100;  // smaller than any field
  Evaluator ev(options);
  Graph g;
  g.add_node("TestSource", "s");
  const auto r = ev.evaluate(g, request({"s"}));
  ASSERT_TRUE(r.ok());
  ASSERT_TRUE(field(r, g, "s"));
  EXPECT_EQ(field(r, g, "s")->data.size(), kDomain.sample_count());
  EXPECT_EQ(ev.cache_stats().entries, 0u);
  EXPECT_EQ(status(ev.evaluate(g, request({"s"})), "s"), NodeStatus::Computed);
  EXPECT_EQ(g_source_runs, 2);
}

TEST_F(EvaluatorTest, IntermediateValuesAreReleasedWhenTheirConsumersAreDone) {
  // source -> a -> probe: when probe runs, a has consumed the source's field and nothing else needs it.
  EvaluatorOptions options;
  options.cache_bytes = 0;  // so the cache does not keep it alive either
  Evaluator ev(options);
  Graph g;
  g.add_node("TestSource", "source");
  g.add_node("TestAdd", "a");
  g.add_node("TestProbe", "probe");
  g.connect({"source", "out"}, "a", "a");
  g.connect({"a", "out"}, "probe", "in");
  ASSERT_TRUE(ev.evaluate(g, request({"probe"})).ok());
  EXPECT_EQ(g_probe_saw_source_alive, 0);
  // Requested values are kept for the result.
  ASSERT_TRUE(ev.evaluate(g, request({"probe", "source"})).ok());
  EXPECT_EQ(g_probe_saw_source_alive, 1);
}

TEST_F(EvaluatorTest, KeepInMemoryLeavesOnlyTheChosenResultsInTheCache) {
  // A tiled build's choice (cli/tile_memory.h): with a cache far larger than the values, only the kept keys stay,
  // and the others live only while a node of the evaluation needs them.
  Graph g;
  g.add_node("TestSource", "source");
  g.add_node("TestAdd", "a");
  g.add_node("TestProbe", "probe");
  g.connect({"source", "out"}, "a", "a");
  g.connect({"a", "out"}, "probe", "in");
  const auto keys = compute_cache_keys(g, test::kEvalDomain);
  Evaluator ev;
  auto keep_a = request({"probe"});
  keep_a.keep_in_memory = [&](const CacheKey& k) { return k == keys.at("a"); };
  ASSERT_TRUE(ev.evaluate(g, keep_a).ok());
  EXPECT_EQ(g_probe_saw_source_alive, 0) << "the source is released once 'a' has used it";
  EXPECT_EQ(ev.cache_stats().entries, 1u);
  // The kept result is found, then dropped when nothing is kept: nothing stays.
  auto keep_nothing = request({"probe"});
  keep_nothing.keep_in_memory = [](const CacheKey&) { return false; };
  const auto r = ev.evaluate(g, keep_nothing);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(status(r, "a"), NodeStatus::Cached);
  EXPECT_EQ(g_add_runs, 1);
  EXPECT_EQ(ev.cache_stats().entries, 0u);
  // Without the choice, everything computed is kept.
  ASSERT_TRUE(ev.evaluate(g, request({"probe"})).ok());
  EXPECT_EQ(g_source_runs, 2);
  EXPECT_EQ(ev.cache_stats().entries, 3u);
}

TEST_F(EvaluatorTest, PersistentCacheIsSharedAcrossEvaluators) {
  const auto dir = test::scratch_dir("eval-persist");
  const Graph g = two_branches();
  EvaluatorOptions options;
  options.cache_dir = dir;
  HeightfieldPtr first;
  {
    Evaluator ev(options);
    const auto r = ev.evaluate(g, request({"b"}));
    ASSERT_TRUE(r.ok());
    first = field(r, g, "b");
    EXPECT_EQ(ev.cache_stats().disk_writes, 3u);
  }
  Evaluator ev2(options);
  const auto r = ev2.evaluate(g, request({"b"}));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(status(r, "b"), NodeStatus::Cached);
  EXPECT_EQ(g_source_runs, 1);
  EXPECT_EQ(g_add_runs, 2);
  EXPECT_EQ(ev2.cache_stats().disk_hits, 1u);
  EXPECT_EQ(ev2.cache_stats().hits, 1u);
  ASSERT_TRUE(field(r, g, "b"));
  EXPECT_EQ(field(r, g, "b")->data, first->data);
  EXPECT_EQ(field(r, g, "b")->domain, first->domain);
  // Loaded entries go to memory too: a second request does not read the disk again.
  EXPECT_EQ(status(ev2.evaluate(g, request({"b"})), "b"), NodeStatus::Cached);
  EXPECT_EQ(ev2.cache_stats().disk_hits, 1u);
  EXPECT_EQ(ev2.cache_stats().hits, 2u);
}

// A source, three delays that each take 0.4 of what an entry of their value costs, then one that takes 2.
Graph delay_chain(double entry_ms) {
  Graph g;
  g.add_node("TestSource", "s");
  std::string upstream = "s";
  for (const auto& [id, share] : {std::pair{"d1", 0.4}, {"d2", 0.4}, {"d3", 0.4}, {"slow", 2.0}}) {
    g.add_node("TestDelay", id).params["milliseconds"] = share * entry_ms;
    g.connect({upstream, "out"}, id, "in");
    upstream = id;
  }
  return g;
}

// The cache directory keeps what a later run could not get back more cheaply by recomputing it. Sleeps bound the
// compute times from below; a loaded machine only makes more values worth storing, and no time is asserted.
TEST_F(EvaluatorTest, CacheDirectoryKeepsWhatCostsMoreToRecomputeThanToStore) {
  const auto dir = test::scratch_dir("eval-worth-storing");
  const Domain big = Domain::from_extent({0.0, 0.0}, {1000.0, 1000.0}, {1025, 1025});  // 4 MiB per field
  const double entry_ms = 1025.0 * 1025.0 * sizeof(float) / double(1 << 20) * DiskCache::kStoreAndLoadMsPerMiB;
  const Graph g = delay_chain(entry_ms);
  EvaluatorOptions options;
  options.cache_dir = dir;
  { ASSERT_TRUE(Evaluator(options).evaluate(g, request({"slow"}, big)).ok()); }
  const auto keys = compute_cache_keys(g, big);
  const DiskCache cache(dir);
  ASSERT_FALSE(cache.stores_everything());
  const auto stored = [&](const char* id) { return std::filesystem::exists(cache.path_of(keys.at(id))); };
  EXPECT_TRUE(stored("slow"));
  // Recomputing d1 to d3 costs more than an entry: one of them is stored, though none alone is worth it.
  EXPECT_TRUE(stored("d1") || stored("d2") || stored("d3"));
  // A re-run of the same request computes nothing; one that needs d3 recomputes at most two cheap delays.
  Evaluator warm(options);
  const auto again = warm.evaluate(g, request({"slow"}, big));
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(status(again, "slow"), NodeStatus::Cached);
  EXPECT_EQ(g_delay_runs, 4);
  const auto d3 = Evaluator(options).evaluate(g, request({"d3"}, big));
  ASSERT_TRUE(d3.ok());
  EXPECT_LE(g_delay_runs, 4 + 2);
  ASSERT_TRUE(field(d3, g, "d3"));
  EXPECT_EQ(field(d3, g, "d3")->at(7, 7), 4.0f);  // 1 + three delays
}

TEST_F(EvaluatorTest, CacheStoreAllKeepsEveryValue) {
  const auto dir = test::scratch_dir("eval-store-all");
  const Domain big = Domain::from_extent({0.0, 0.0}, {1000.0, 1000.0}, {1025, 1025});
  ASSERT_EQ(::setenv("OROGEN_CACHE_STORE", "all", 1), 0);
  EvaluatorOptions options;
  options.cache_dir = dir;
  {
    Evaluator ev(options);
    const bool ok = ev.evaluate(delay_chain(0.0), request({"slow"}, big)).ok();
    ::unsetenv("OROGEN_CACHE_STORE");
    ASSERT_TRUE(ok);
    EXPECT_EQ(ev.cache_stats().disk_writes, 5u);
  }
  const Graph g = delay_chain(0.0);
  for (const auto& [id, key] : compute_cache_keys(g, big))
    EXPECT_TRUE(std::filesystem::exists(DiskCache(dir).path_of(key))) << id;
}

// Damages the disk entry of node `id` and checks that a fresh evaluator rejects and recomputes it.
void expect_damaged_entry_recomputed(const std::function<void(const std::filesystem::path&)>& damage) {
  reset_counters();
  const auto dir = test::scratch_dir("eval-damaged");
  Graph g;
  g.add_node("TestSource", "s").params["value"] = 7.0;
  EvaluatorOptions options;
  options.cache_dir = dir;
  { ASSERT_TRUE(Evaluator(options).evaluate(g, request({"s"})).ok()); }
  const auto key = compute_cache_keys(g, kDomain).at("s");
  const auto file = DiskCache(dir).path_of(key);
  ASSERT_TRUE(std::filesystem::exists(file));
  damage(file);

  const int runs_before = g_source_runs;
  Evaluator ev(options);
  const auto r = ev.evaluate(g, request({"s"}));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(status(r, "s"), NodeStatus::Computed);
  EXPECT_EQ(g_source_runs, runs_before + 1);
  EXPECT_EQ(ev.cache_stats().disk_rejected, 1u);
  EXPECT_EQ(ev.cache_stats().disk_hits, 0u);
  EXPECT_EQ(field(r, g, "s")->at(5, 5), 7.0f);
  // The recomputed result replaced the damaged entry.
  Evaluator ev3(options);
  EXPECT_EQ(status(ev3.evaluate(g, request({"s"})), "s"), NodeStatus::Cached);
  EXPECT_EQ(ev3.cache_stats().disk_hits, 1u);
}

TEST_F(EvaluatorTest, CorruptedDiskEntryIsRecomputed) {
  expect_damaged_entry_recomputed([](const std::filesystem::path& file) {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(DiskCache::kHeaderBytes + 200));
    f.put('\x5a');
  });
}

TEST_F(EvaluatorTest, TruncatedDiskEntryIsRecomputed) {
  expect_damaged_entry_recomputed([](const std::filesystem::path& file) {
    std::filesystem::resize_file(file, std::filesystem::file_size(file) / 2);
  });
}

TEST_F(EvaluatorTest, DiskEntryUnderTheWrongKeyIsRecomputed) {
  expect_damaged_entry_recomputed([](const std::filesystem::path& file) {
    // A valid entry of another key, copied over this one.
    Graph other;
    other.add_node("TestSource", "s").params["value"] = 8.0;
    const auto dir = test::scratch_dir("eval-other");
    EvaluatorOptions options;
    options.cache_dir = dir;
    ASSERT_TRUE(Evaluator(options).evaluate(other, request({"s"})).ok());
    const auto other_file = DiskCache(dir).path_of(compute_cache_keys(other, kDomain).at("s"));
    std::filesystem::copy_file(other_file, file, std::filesystem::copy_options::overwrite_existing);
  });
}

// A graph with independent row-parallel branches joined at the end.
Graph ripple_graph() {
  Graph g;
  g.add_node("TestRipple", "r1").params["wavelength"] = 37.0;
  g.add_node("TestRipple", "r2").params["wavelength"] = 91.0;
  g.add_node("TestRipple", "r3").params["wavelength"] = 13.0;
  g.add_node("TestRipple", "r4").params["wavelength"] = 55.0;
  g.connect({"r1", "out"}, "r3", "in");
  g.add_node("TestAdd", "sum");
  g.connect({"r3", "out"}, "sum", "a");
  g.connect({"r2", "out"}, "sum", "b");
  g.connect({"sum", "out"}, "r4", "in");
  return g;
}

TEST_F(EvaluatorTest, OneAndFourThreadsAreBitIdentical) {
  // Allow four threads even on a smaller machine, so the four-thread run really splits the work.
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 4);
  const Graph g = ripple_graph();
  const Domain d = Domain::from_extent({-500.0, 250.0}, {2000.0, 1500.0}, {257, 193});
  std::vector<float> results[2];
  int slot = 0;
  for (int threads : {1, 4}) {
    EvaluatorOptions options;
    options.threads = threads;
    Evaluator ev(options);
    const auto r = ev.evaluate(g, request({"r4"}, d));
    ASSERT_TRUE(r.ok());
    results[slot++] = field(r, g, "r4")->data;
  }
  ASSERT_EQ(results[0].size(), d.sample_count());
  ASSERT_EQ(results[0].size(), results[1].size());
  EXPECT_EQ(std::memcmp(results[0].data(), results[1].data(), results[0].size() * sizeof(float)), 0);
  EXPECT_EQ(g_ripple_runs, 8);
}

TEST_F(EvaluatorTest, CancellationFromAnotherThread) {
  const auto dir = test::scratch_dir("eval-cancel");
  Graph g;
  g.add_node("TestSource", "source");
  g.add_node("TestSlow", "slow");
  g.add_node("TestAdd", "after");
  g.connect({"source", "out"}, "slow", "in");
  g.connect({"slow", "out"}, "after", "a");
  EvaluatorOptions options;
  options.cache_dir = dir;
  options.threads = 1;  // so the independent source2 below cannot start while slow is running
  Evaluator ev(options);
  CancelToken cancel;
  auto req = request({"after"});
  req.cancel = &cancel;
  std::vector<EvalEvent> events;
  req.on_event = [&](const EvalEvent& e) { events.push_back(e); };

  std::thread canceller([&] {
    std::unique_lock lock(g_slow_mutex);
    g_slow_cv.wait(lock, [] { return g_slow_started; });
    cancel.cancel();
  });
  const auto r = ev.evaluate(g, req);
  canceller.join();

  EXPECT_TRUE(r.cancelled);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(status(r, "slow"), NodeStatus::Cancelled);
  EXPECT_EQ(status(r, "after"), NodeStatus::Cancelled);
  EXPECT_EQ(g_add_runs, 0) << "pending nodes are not started";
  for (const auto& [id, report] : r.nodes) EXPECT_NE(report.status, NodeStatus::Failed) << id;
  EXPECT_TRUE(r.outputs.empty());
  const auto keys = compute_cache_keys(g, kDomain);
  EXPECT_FALSE(std::filesystem::exists(DiskCache(dir).path_of(keys.at("slow")))) << "nothing partial is cached";
  int cancelled_events = 0;
  for (const auto& e : events) cancelled_events += e.kind == EvalEvent::Kind::Cancelled;
  EXPECT_EQ(cancelled_events, 2);

  // The source completed before the cancel: a correct, content-addressed result that may stay cached.
  // The cancelled node was not cached: it runs again.
  cancel.reset();
  g_slow_release = true;
  const auto again = ev.evaluate(g, req);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(status(again, "source"), NodeStatus::Cached);
  EXPECT_EQ(status(again, "slow"), NodeStatus::Computed);
  EXPECT_EQ(g_slow_runs, 2);
  EXPECT_EQ(g_source_runs, 1);
}

TEST_F(EvaluatorTest, CancelledBeforeStartRunsNothing) {
  const Graph g = two_branches();
  Evaluator ev;
  CancelToken cancel;
  cancel.cancel();
  auto req = request({"b", "c"});
  req.cancel = &cancel;
  const auto r = ev.evaluate(g, req);
  EXPECT_TRUE(r.cancelled);
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(g_source_runs + g_add_runs, 0);
  for (const auto& [id, report] : r.nodes) EXPECT_EQ(report.status, NodeStatus::Cancelled) << id;
  EXPECT_EQ(ev.cache_stats().entries, 0u);
}

TEST_F(EvaluatorTest, ErrorsStayLocal) {
  Graph g;
  g.add_node("TestSource", "source");
  g.add_node("TestFail", "broken");
  g.add_node("TestAdd", "after_broken");
  g.add_node("TestAdd", "after_after");
  g.add_node("TestAdd", "independent");
  g.connect({"source", "out"}, "broken", "in");
  g.connect({"broken", "out"}, "after_broken", "a");
  g.connect({"after_broken", "out"}, "after_after", "a");
  g.connect({"source", "out"}, "independent", "a");
  Evaluator ev;
  const auto r = ev.evaluate(g, request({"after_after", "independent"}));
  EXPECT_FALSE(r.ok());
  EXPECT_FALSE(r.cancelled);
  EXPECT_EQ(status(r, "broken"), NodeStatus::Failed);
  EXPECT_EQ(r.nodes.at("broken").message, "deliberate failure");
  EXPECT_EQ(status(r, "after_broken"), NodeStatus::Skipped);
  EXPECT_EQ(r.nodes.at("after_broken").message, "broken");
  EXPECT_EQ(status(r, "after_after"), NodeStatus::Skipped);
  EXPECT_EQ(r.nodes.at("after_after").message, "broken");
  EXPECT_EQ(status(r, "independent"), NodeStatus::Computed);
  EXPECT_TRUE(field(r, g, "independent"));
  EXPECT_EQ(r.outputs.count("after_after"), 0u);
  EXPECT_EQ(g_add_runs, 1);

  // Errors are never cached: the failing node runs again.
  const auto again = ev.evaluate(g, request({"after_after", "independent"}));
  EXPECT_EQ(g_fail_runs, 2);
  EXPECT_EQ(status(again, "independent"), NodeStatus::Cached);
}

TEST_F(EvaluatorTest, FailureMessages) {
  Graph g;
  g.add_node("TestSource", "source");
  g.add_node("TestFail", "std_error").params["how"] = std::string("std_exception");
  g.add_node("TestFail", "no_output").params["how"] = std::string("no_output");
  g.add_node("TestAdd", "unconnected");  // required input 'a' missing
  g.add_node("TestAdd", "bad_link");
  g.add_node("TestAdd", "after_bad_link");
  g.connect({"bad_link", "out"}, "after_bad_link", "a");
  // Links that Graph::connect would refuse, as a hand-edited graph might hold them.
  g.find("bad_link")->inputs["a"] = PortRef{"nowhere", "out"};
  g.add_node("TestAdd", "bad_port");
  g.find("bad_port")->inputs["a"] = PortRef{"source", "nope"};
  g.add_node("TestAdd", "unknown_input");
  g.find("unknown_input")->inputs["zzz"] = PortRef{"source", "out"};
  Evaluator ev;
  const auto r = ev.evaluate(
      g, request({"std_error", "no_output", "unconnected", "after_bad_link", "bad_port", "unknown_input", "source"}));
  EXPECT_FALSE(r.ok());
  EXPECT_EQ(r.nodes.at("std_error").message, "a std::runtime_error");
  EXPECT_NE(r.nodes.at("no_output").message.find("output 'out'"), std::string::npos) << r.nodes.at("no_output").message;
  EXPECT_EQ(r.nodes.at("unconnected").message, "required input 'a' is not connected");
  EXPECT_EQ(status(r, "bad_link"), NodeStatus::Failed);
  EXPECT_NE(r.nodes.at("bad_link").message.find("missing node 'nowhere'"), std::string::npos);
  EXPECT_EQ(status(r, "after_bad_link"), NodeStatus::Skipped);
  EXPECT_EQ(r.nodes.at("after_bad_link").message, "bad_link");
  EXPECT_NE(r.nodes.at("bad_port").message.find("no output 'nope'"), std::string::npos);
  EXPECT_NE(r.nodes.at("unknown_input").message.find("no input 'zzz'"), std::string::npos);
  EXPECT_EQ(status(r, "source"), NodeStatus::Computed);
  EXPECT_EQ(g_add_runs, 0);
  const auto keys = compute_cache_keys(g, kDomain);
  EXPECT_EQ(keys.count("bad_link"), 0u);
  EXPECT_EQ(keys.count("after_bad_link"), 0u);
  EXPECT_EQ(keys.count("source"), 1u);
}

TEST_F(EvaluatorTest, RunNodeHasTheSameOutputContract) {
  try {
    run_node("TestFail", kDomain, {{"how", std::string("no_output")}});
    ADD_FAILURE() << "expected a NodeError";
  } catch (const NodeError& e) {
    EXPECT_NE(std::string(e.what()).find("output 'out'"), std::string::npos) << e.what();
  }
  const auto run = run_node("TestSource", kDomain, {{"value", 4.0}});
  EXPECT_EQ(run.get<Heightfield>()->at(1, 1), 4.0f);
}

TEST_F(EvaluatorTest, UnknownRequestedNodeThrows) {
  Evaluator ev;
  EXPECT_THROW(ev.evaluate(two_branches(), request({"nope"})), GraphError);
}

TEST_F(EvaluatorTest, DefaultRequestIsEverySinkAndWriter) {
  const auto dir = test::scratch_dir("eval-default");
  Graph g = two_branches();
  g.add_node("TestWriter", "writer");
  g.connect({"a", "out"}, "writer", "in");
  Evaluator ev(writing_to(dir));
  const auto r = ev.evaluate(g, request({}));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r.outputs.size(), 3u);  // b, c and the writer
  EXPECT_TRUE(r.outputs.count("b") && r.outputs.count("c") && r.outputs.count("writer"));
  EXPECT_TRUE(std::filesystem::exists(dir / "sum.txt"));
}

TEST_F(EvaluatorTest, EventSequence) {
  Graph g;
  g.add_node("TestSource", "source");
  g.add_node("TestProgress", "progress");
  g.add_node("TestFail", "broken");
  g.add_node("TestAdd", "skipped");
  g.connect({"source", "out"}, "progress", "in");
  g.connect({"broken", "out"}, "skipped", "a");
  Evaluator ev;
  auto req = request({"progress", "skipped"});
  std::vector<EvalEvent> events;
  req.on_event = [&](const EvalEvent& e) { events.push_back(e); };
  const auto r = ev.evaluate(g, req);

  auto of = [&](const std::string& node) {
    std::vector<EvalEvent> out;
    for (const auto& e : events)
      if (e.node == node) out.push_back(e);
    return out;
  };
  for (const std::string node : {"source", "progress"}) {
    const auto ev_node = of(node);
    ASSERT_GE(ev_node.size(), 2u) << node;
    EXPECT_EQ(ev_node.front().kind, EvalEvent::Kind::Started) << node;
    EXPECT_EQ(ev_node.back().kind, EvalEvent::Kind::Finished) << node;
    EXPECT_EQ(ev_node.back().output_bytes, r.nodes.at(node).output_bytes);
    EXPECT_GT(ev_node.back().output_bytes, kDomain.sample_count() * sizeof(float) - 1);
    EXPECT_GE(ev_node.back().milliseconds, 0.0);
    double last = -1.0;
    for (std::size_t k = 1; k + 1 < ev_node.size(); ++k) {
      EXPECT_EQ(ev_node[k].kind, EvalEvent::Kind::Progress);
      EXPECT_GT(ev_node[k].fraction, last);
      EXPECT_LE(ev_node[k].fraction, 1.0);
      last = ev_node[k].fraction;
    }
  }
  EXPECT_GE(of("progress").size(), 3u) << "at least one progress event";
  EXPECT_LE(of("progress").size(), 2u + 51u) << "progress events are rate-limited";
  // The source finished before the node that reads it started.
  std::size_t source_finished = 0, progress_started = 0;
  for (std::size_t k = 0; k < events.size(); ++k) {
    if (events[k].node == "source" && events[k].kind == EvalEvent::Kind::Finished) source_finished = k;
    if (events[k].node == "progress" && events[k].kind == EvalEvent::Kind::Started) progress_started = k;
  }
  EXPECT_LT(source_finished, progress_started);

  const auto broken = of("broken");
  ASSERT_EQ(broken.size(), 2u);
  EXPECT_EQ(broken[1].kind, EvalEvent::Kind::Failed);
  EXPECT_EQ(broken[1].message, "deliberate failure");
  const auto skipped = of("skipped");
  ASSERT_EQ(skipped.size(), 1u);
  EXPECT_EQ(skipped[0].kind, EvalEvent::Kind::Skipped);
  EXPECT_EQ(skipped[0].message, "broken");

  // A second evaluation: one Cached event for the requested node, nothing for its upstream.
  events.clear();
  req.nodes = {"progress"};
  ev.evaluate(g, req);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, EvalEvent::Kind::Cached);
  EXPECT_EQ(events[0].node, "progress");
  EXPECT_EQ(events[0].output_bytes, r.nodes.at("progress").output_bytes);
}

TEST_F(EvaluatorTest, WriterRunsAgainWhenItsFileIsDeletedOrChanged) {
  const auto dir = test::scratch_dir("eval-writer");
  Graph g;
  g.add_node("TestSource", "source").params["value"] = 2.0;
  g.add_node("TestWriter", "writer");
  g.connect({"source", "out"}, "writer", "in");
  EvaluatorOptions options;
  options.output = {dir / "out", false};
  options.cache_dir = dir / "cache";
  Evaluator ev(options);
  const auto file = dir / "out" / "sum.txt";

  ASSERT_TRUE(ev.evaluate(g, request({"writer"})).ok());
  EXPECT_EQ(g_writer_runs, 1);
  ASSERT_TRUE(std::filesystem::exists(file));

  auto r = ev.evaluate(g, request({"writer"}));
  EXPECT_EQ(status(r, "writer"), NodeStatus::Cached) << "file unchanged: a second run is entirely cached";
  EXPECT_EQ(r.nodes.size(), 1u);
  EXPECT_EQ(g_writer_runs, 1);
  { EXPECT_EQ(status(Evaluator(options).evaluate(g, request({"writer"})), "writer"), NodeStatus::Cached); }

  std::filesystem::remove(file);
  r = ev.evaluate(g, request({"writer"}));
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(status(r, "writer"), NodeStatus::Computed);
  EXPECT_EQ(status(r, "source"), NodeStatus::Cached) << "the writer's input comes from the cache";
  EXPECT_EQ(g_writer_runs, 2);
  EXPECT_EQ(g_source_runs, 1);
  EXPECT_TRUE(std::filesystem::exists(file));

  write_text_atomically(file, "edited by hand, longer than before\n");
  r = ev.evaluate(g, request({"writer"}));
  EXPECT_EQ(status(r, "writer"), NodeStatus::Computed);
  EXPECT_EQ(g_writer_runs, 3);

  // Also across processes: a new evaluator with the same cache directory notices the deleted file.
  std::filesystem::remove(file);
  Evaluator fresh(options);
  EXPECT_EQ(status(fresh.evaluate(g, request({"writer"})), "writer"), NodeStatus::Computed);
  EXPECT_EQ(g_writer_runs, 4);
  EXPECT_TRUE(std::filesystem::exists(file));
}

TEST_F(EvaluatorTest, OutputDirectoryIsPartOfAWritersKeyOnly) {
  Graph g;
  g.add_node("TestSource", "source");
  g.add_node("TestWriter", "writer");
  g.connect({"source", "out"}, "writer", "in");
  const auto a = compute_cache_keys(g, kDomain, {"out-a", false});
  const auto b = compute_cache_keys(g, kDomain, {"out-b", false});
  EXPECT_EQ(a.at("source"), b.at("source"));
  EXPECT_NE(a.at("writer"), b.at("writer"));
}

TEST_F(EvaluatorTest, RefusedOutputPathFailsTheWriter) {
  Graph g;
  g.add_node("TestSource", "source");
  g.add_node("TestWriter", "writer").params["path"] = std::string("../escape.txt");
  g.connect({"source", "out"}, "writer", "in");
  Evaluator ev(writing_to(test::scratch_dir("eval-refused")));
  const auto r = ev.evaluate(g, request({"writer"}));
  EXPECT_EQ(status(r, "writer"), NodeStatus::Failed);
  EXPECT_NE(r.nodes.at("writer").message.find(".."), std::string::npos) << r.nodes.at("writer").message;
}

TEST_F(EvaluatorTest, KeysDoNotDependOnIdsPositionsOrNodeOrder) {
  Graph a;
  a.add_node("TestSource", "s").params["value"] = 4.0;
  a.add_node("TestAdd", "x");
  a.connect({"s", "out"}, "x", "a");
  a.editor.positions["s"] = {0, 0};

  Graph b;
  b.add_node("TestAdd", "sum_node");  // other ids, other order, other positions
  b.add_node("TestRipple", "unrelated");
  b.add_node("TestSource", "height_source").params["value"] = 4.0;
  b.connect({"height_source", "out"}, "sum_node", "a");
  b.editor.positions["sum_node"] = {300, -20};
  b.editor.positions["height_source"] = {-7, 8};

  const auto ka = compute_cache_keys(a, kDomain), kb = compute_cache_keys(b, kDomain);
  EXPECT_EQ(ka.at("s"), kb.at("height_source"));
  EXPECT_EQ(ka.at("x"), kb.at("sum_node"));
  // But the domain does enter it.
  const auto kc = compute_cache_keys(a, kDomain.resampled({17, 16}));
  EXPECT_NE(ka.at("x"), kc.at("x"));
  // Explicitly setting a parameter to its default is the same key as leaving it unset.
  a.set_param("x", "offset", 0.0);
  EXPECT_EQ(compute_cache_keys(a, kDomain).at("x"), ka.at("x"));
  // A same-domain evaluation through different evaluators reports the same key.
  EXPECT_EQ(Evaluator().evaluate(a, request({"x"})).nodes.at("x").key, ka.at("x"));
}

TEST_F(EvaluatorTest, IndependentBranchesRunConcurrently) {
  tbb::global_control allow(tbb::global_control::max_allowed_parallelism, 2);
  Graph g;
  g.add_node("TestRendezvous", "left").params["tag"] = std::int64_t{1};
  g.add_node("TestRendezvous", "right").params["tag"] = std::int64_t{2};
  g.add_node("TestAdd", "join");
  g.connect({"left", "out"}, "join", "a");
  g.connect({"right", "out"}, "join", "b");
  EvaluatorOptions options;
  options.threads = 2;
  ASSERT_TRUE(Evaluator(options).evaluate(g, request({"join"})).ok());
  EXPECT_EQ(g_rendezvous_met, 2) << "the two branches never ran at the same time";
}

TEST_F(EvaluatorTest, ManyIndependentBranchesInParallel) {
  // A wide graph: 40 ripples feeding a tree of adds. Every node runs once, in any order the threads like.
  Graph g;
  std::vector<std::string> level;
  for (int k = 0; k < 40; ++k) {
    const auto id = numbered("r", k);
    g.add_node("TestRipple", id).params["wavelength"] = 10.0 + k;
    level.push_back(id);
  }
  int n = 0;
  while (level.size() > 1) {
    std::vector<std::string> next;
    for (std::size_t k = 0; k + 1 < level.size(); k += 2) {
      const auto id = numbered("add", n++);
      g.add_node("TestAdd", id);
      g.connect({level[k], "out"}, id, "a");
      g.connect({level[k + 1], "out"}, id, "b");
      next.push_back(id);
    }
    if (level.size() % 2) next.push_back(level.back());
    level = next;
  }
  const Domain d = Domain::from_extent({0, 0}, {1000, 1000}, {48, 48});
  EvaluatorOptions one;
  one.threads = 1;
  const auto r1 = Evaluator(one).evaluate(g, request({level[0]}, d));
  const auto rn = Evaluator().evaluate(g, request({level[0]}, d));
  ASSERT_TRUE(r1.ok());
  ASSERT_TRUE(rn.ok());
  EXPECT_EQ(g_ripple_runs, 80);
  EXPECT_EQ(g_add_runs, 2 * n);
  EXPECT_EQ(field(r1, g, level[0])->data, field(rn, g, level[0])->data);
}

// Tiled builds: a node given a domain of its own runs on it, with its raster inputs cut from a larger domain
// of the same lattice; the domain is part of its key.
TEST_F(EvaluatorTest, NodeDomainsRunNodesOnTheirOwnDomainWithCroppedInputs) {
  Graph g;
  g.add_node("TestRipple", "ripple");
  g.add_node("TestAdd", "sum").params["offset"] = 0.5;
  g.connect({"ripple", "out"}, "sum", "a");
  g.connect({"ripple", "out"}, "sum", "b");
  Evaluator ev;
  const auto whole = ev.evaluate(g, request({"sum"}));
  ASSERT_TRUE(whole.ok());

  const Domain tile = kDomain.subdomain(4, 5, 6, 7);
  EvalRequest r = request({"sum", "ripple"});
  r.node_domains = {{"ripple", kDomain.subdomain(2, 3, 10, 11)}, {"sum", tile}};
  const auto tiled = ev.evaluate(g, r);
  ASSERT_TRUE(tiled.ok());
  EXPECT_EQ(status(tiled, "ripple"), NodeStatus::Computed);  // another domain, another key
  EXPECT_NE(tiled.nodes.at("sum").key, whole.nodes.at("sum").key);
  ASSERT_TRUE(field(tiled, g, "ripple"));
  EXPECT_EQ(field(tiled, g, "ripple")->domain, kDomain.subdomain(2, 3, 10, 11));
  const auto sum = field(tiled, g, "sum");
  ASSERT_TRUE(sum);
  EXPECT_EQ(sum->domain, tile);
  const auto full = field(whole, g, "sum");
  for (int j = 0; j < tile.height(); ++j)
    for (int i = 0; i < tile.width(); ++i) ASSERT_EQ(sum->at(i, j), full->at(4 + i, 5 + j)) << i << "," << j;

  // The same node domains again: everything is found in the cache.
  const auto again = ev.evaluate(g, r);
  EXPECT_EQ(status(again, "sum"), NodeStatus::Cached);
  EXPECT_EQ(status(again, "ripple"), NodeStatus::Cached);
  // A node domain equal to the request's is the untiled result.
  EvalRequest same = request({"sum"});
  same.node_domains = {{"sum", kDomain}, {"ripple", kDomain}};
  EXPECT_EQ(ev.evaluate(g, same).nodes.at("sum").key, whole.nodes.at("sum").key);
}

TEST(DomainCrop, CutsRastersOnTheSameLatticeAndLeavesTheRestAlone) {
  const Domain d = Domain::from_extent({10.0, -20.0}, {90.0, 60.0}, {10, 7});
  auto h = std::make_shared<Heightfield>(d);
  auto im = std::make_shared<Image>(d, 3);
  im->channel_names = {"R", "G", "B"};
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) {
      h->at(i, j) = static_cast<float>(100 * j + i);
      for (int c = 0; c < 3; ++c) im->pixel(i, j)[c] = static_cast<float>(1000 * c + 100 * j + i);
    }
  const Domain inner = d.subdomain(3, 2, 4, 5);
  const auto hc = std::get<HeightfieldPtr>(crop_to_domain(HeightfieldPtr(h), inner));
  EXPECT_EQ(hc->domain, inner);
  const auto ic = std::get<ImagePtr>(crop_to_domain(ImagePtr(im), inner));
  EXPECT_EQ(ic->domain, inner);
  EXPECT_EQ(ic->channel_names, im->channel_names);
  for (int j = 0; j < inner.height(); ++j)
    for (int i = 0; i < inner.width(); ++i) {
      EXPECT_EQ(hc->at(i, j), static_cast<float>(100 * (j + 2) + i + 3));
      for (int c = 0; c < 3; ++c) EXPECT_EQ(ic->pixel(i, j)[c], static_cast<float>(1000 * c + 100 * (j + 2) + i + 3));
    }
  // Nested sub-domains cut relative to their own first sample.
  const auto nested = std::get<HeightfieldPtr>(crop_to_domain(hc, inner.subdomain(1, 1, 2, 2)));
  EXPECT_EQ(nested->at(0, 0), static_cast<float>(100 * 3 + 4));
  // Not contained, another lattice, or the same domain: passed through untouched.
  const HeightfieldPtr hp = h;
  EXPECT_EQ(std::get<HeightfieldPtr>(crop_to_domain(hp, d)), hp);
  EXPECT_EQ(std::get<HeightfieldPtr>(crop_to_domain(hp, d.subdomain(5, 0, 6, 3))), hp);  // beyond the right edge
  EXPECT_EQ(std::get<HeightfieldPtr>(crop_to_domain(hp, d.resampled({19, 13}))), hp);
  EXPECT_FALSE(domain_contains(d, d.subdomain(-1, 0, 3, 3)));
  EXPECT_TRUE(domain_contains(d, d.subdomain(9, 6, 1, 1)));
}

// Points computed on a larger domain reach a node on a tile as the points inside the tile, borders included, with
// their rotations, scales, classes and attributes; on the same domain (an untiled build) every point stays.
TEST(DomainCrop, PointsOfALargerDomainAreCutToTheTileBordersIncluded) {
  const Domain d = Domain::from_extent({0, 0}, {100, 60}, {11, 7});  // samples every 10 m
  auto pts = std::make_shared<Points>();
  const glm::vec3 at[] = {{5, 5, 1}, {20, 10, 2}, {40, 30, 3}, {41, 30, 4}, {30, 20, 5}, {-1, 10, 6}, {35, 25, 7}};
  for (int k = 0; k < 7; ++k) {
    pts->add(at[k], k);
    pts->scale.back() = glm::vec3(static_cast<float>(k));
  }
  auto& age = pts->attribute("age");
  for (int k = 0; k < 7; ++k) age[static_cast<std::size_t>(k)] = 10.0f * static_cast<float>(k);
  const PortValue value = std::shared_ptr<const Points>(pts);
  const Domain tile = d.subdomain(2, 1, 3, 3);  // x in [20, 40], y in [10, 30]
  const auto cut = std::get<std::shared_ptr<const Points>>(crop_points_to_domain(value, d, tile));
  ASSERT_EQ(cut->size(), 4u);  // (20, 10) and (40, 30) on the tile's corners, (30, 20) and (35, 25) inside
  const int kept[] = {1, 2, 4, 6};
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_EQ(cut->position[k], at[kept[k]]);
    EXPECT_EQ(cut->class_id[k], kept[k]);
    EXPECT_EQ(cut->scale[k], glm::vec3(static_cast<float>(kept[k])));
    EXPECT_EQ(cut->attributes.at("age")[k], 10.0f * static_cast<float>(kept[k]));
  }
  cut->check_consistent();
  EXPECT_EQ(std::get<std::shared_ptr<const Points>>(crop_points_to_domain(value, d, d)), pts);     // the same domain
  EXPECT_EQ(std::get<std::shared_ptr<const Points>>(crop_points_to_domain(value, tile, d)), pts);  // not contained
}

}  // namespace
}  // namespace orogen
