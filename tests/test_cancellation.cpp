// Cancellation within a bound, for every node type: each is run at costly legal parameters on a small domain
// (so setting up stays cheap), cancelled after kCancelAfter, and must return (with a result, a clear error
// or Cancelled) within kBound of the cancel. Generated from the registry: a new node type is covered without
// touching this file. The repros of issue #30 (a droplet of 1e7 steps, a river network of two million points
// with a search radius over the whole map, shadow marches of 1e9 steps, a cell locator on a 1 x 1e7 map) are
// run as named cases.
//
// Each node's case says whether it exercised the cancellation: point-wise nodes finish 33 x 33 before the timed
// cancel (and fail at some parameter extremes before doing anything), so every node is also cancelled at its
// first progress report, on 129 x 129 where its inputs are fields, and must stop there; a node exercised by
// neither case must be listed in kNotExercised with the reason, or the case fails.
//
// The bound (docs/reliability.md, "Cancellation"): 1 s in an optimised build; kSanitizerFactor times that
// under AddressSanitizer, whose every memory access is several times slower.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <condition_variable>
#include <iostream>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "evaluator/run_node.h"
#include "graph/cancel.h"
#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/node_type.h"
#include "graph/points.h"
#include "graph/registry.h"
#include "graph/scene.h"
#include "nodes/io/heightfield_file.h"
#include "nodes/io/image_codec.h"
#include "support/registered_types.h"
#include "support/sample_values.h"
#include "support/sanitizers.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

using Clock = std::chrono::steady_clock;
using Seconds = std::chrono::duration<double>;

#ifdef OROGEN_TEST_ASAN
constexpr double kSanitizerFactor = 5.0;
#else
constexpr double kSanitizerFactor = 1.0;
#endif
constexpr auto kCancelAfter = std::chrono::milliseconds(500);
const double kBound = 1.0 * kSanitizerFactor;  // seconds from the cancel to the node's return

struct Timed {
  bool cancelled_in_flight = false;  // the node was still running when the cancel came
  double latency = 0.0;              // seconds from the cancel to the return
  std::string outcome;               // "result", "cancelled" or the error
};

// Runs the node on this thread; another cancels it after `cancel_after` unless it has returned. With
// `cancel_at_progress`, the node is instead cancelled at its first progress report past that fraction, so a
// fast machine cannot finish before the cancel comes.
Timed run_timed(const std::string& type, const Domain& d, const std::map<std::string, ParamValue>& params,
                const std::map<std::string, PortValue>& inputs, const OutputPolicy& policy,
                std::chrono::milliseconds cancel_after = kCancelAfter,
                std::optional<double> cancel_at_progress = std::nullopt) {
  CancelToken cancel;
  std::mutex m;
  std::condition_variable cv;
  bool done = false;
  Clock::time_point cancelled_at{};
  std::thread watchdog([&] {
    std::unique_lock lock(m);
    if (!cv.wait_for(lock, cancel_after, [&] { return done; }) && cancelled_at == Clock::time_point{}) {
      cancelled_at = Clock::now();
      cancel.cancel();
    }
  });
  std::function<void(double)> on_progress;
  if (cancel_at_progress)
    on_progress = [&](double fraction) {
      std::lock_guard lock(m);
      if (fraction > *cancel_at_progress && cancelled_at == Clock::time_point{}) {
        cancelled_at = Clock::now();
        cancel.cancel();
      }
    };
  Timed t;
  try {
    (void)run_node(type, d, params, inputs, policy, &cancel, on_progress);
    t.outcome = "result";
  } catch (const Cancelled&) {
    t.outcome = "cancelled";
  } catch (const std::logic_error& e) {
    ADD_FAILURE() << type << ": logic_error (a bug, not a clear error): " << e.what();
    t.outcome = e.what();
  } catch (const std::exception& e) {
    t.outcome = e.what();
  }
  const auto returned = Clock::now();
  {
    std::lock_guard lock(m);
    done = true;
  }
  cv.notify_one();
  watchdog.join();
  if (cancelled_at != Clock::time_point{}) {
    t.cancelled_in_flight = true;
    t.latency = Seconds(returned - cancelled_at).count();
  }
  return t;
}

void expect_within_bound(const std::string& label, const Timed& t) {
  if (t.cancelled_in_flight)
    std::cout << label << ": cancelled in flight, returned after " << t.latency * 1e3 << " ms ("
              << t.outcome.substr(0, 200) << ")\n";
  else
    std::cout << label << ": " << t.outcome.substr(0, 200) << "\n";
  EXPECT_LE(t.latency, kBound) << label << ": returned " << t.latency << " s after the cancel (" << t.outcome << ")";
}

HeightfieldPtr bowl(const Domain& d) {
  auto h = std::make_shared<Heightfield>(d);
  const glm::dvec2 c = d.min_corner() + 0.5 * d.size();
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) {
      const glm::dvec2 q = d.position(i, j) - c;
      h->at(i, j) = static_cast<float>(100.0 + 1e-3 * glm::dot(q, q) + 5.0 * std::sin(0.7 * i + 0.3 * j));
    }
  return h;
}

// Every numeric parameter at one end of its declared range ("max": counts, durations, radii at their
// largest; "min": step lengths, time steps, spacings at their smallest). Between them the two cover the
// costly end of every parameter whichever direction costs.
std::map<std::string, ParamValue> at_end(const NodeType& type, bool high) {
  std::map<std::string, ParamValue> out;
  for (const auto& p : type.params) {
    if (p.output_file || p.type == ParamType::Path) continue;
    if (!p.min || !p.max) continue;
    const double v = high ? *p.max : *p.min;
    ParamValue value;
    switch (p.type) {
      case ParamType::Float:
        value = v;
        break;
      case ParamType::Int:
        value = static_cast<std::int64_t>(v);
        break;
      default:
        continue;  // vectors (positions, sizes): their defaults keep the domain in view
    }
    if (p.check(value).empty()) out[p.name] = value;
  }
  return out;
}

const Domain kSmall = Domain::from_extent({0, 0}, {320, 320}, {33, 33});
// Where nodes of field inputs are cancelled at their first progress report: rows enough for several reports.
const Domain kMidRun = Domain::from_extent({0, 0}, {1280, 1280}, {129, 129});

struct MidRun {
  bool reported = false;  // the node reported progress strictly between 0 and 1 (and was cancelled there)
  double fraction = 0.0;  // the first such report
  int reports_after = 0;  // progress reports after the cancel
  std::string outcome;    // "result", "cancelled" or the error
};

// Runs the node with its default parameters and cancels it at its first progress report strictly inside (0, 1).
MidRun cancel_at_first_progress(const std::string& type, const Domain& d,
                                const std::map<std::string, ParamValue>& params,
                                const std::map<std::string, PortValue>& inputs, const OutputPolicy& policy) {
  CancelToken cancel;
  MidRun m;
  std::mutex mutex;  // reports may come from several of TBB's threads
  const auto on_progress = [&](double fraction) {
    std::lock_guard lock(mutex);
    if (m.reported) ++m.reports_after;
    if (m.reported || !(fraction > 0.0 && fraction < 1.0)) return;
    m.reported = true;
    m.fraction = fraction;
    cancel.cancel();
  };
  try {
    (void)run_node(type, d, params, inputs, policy, &cancel, on_progress);
    m.outcome = "result";
  } catch (const Cancelled&) {
    m.outcome = "cancelled";
  } catch (const std::exception& e) {
    m.outcome = e.what();
  }
  return m;
}

// Node types that neither outlast the timed cancel nor report progress before their end, with the reason. Every
// other type must be seen to stop.
const std::map<std::string, std::string> kNotExercised = {
    {"Constant", "one fill of the output by the vector's constructor: no loop of its own"},
    {"FillDepressions", "Priority-Flood reports no progress and polls every 65536 cells: 129^2 ends before one check"},
    {"FloodFill", "Priority-Flood reports no progress and polls every 65536 cells: 129^2 ends before one check"},
    {"Lakes", "Priority-Flood reports no progress and polls every 65536 cells: 129^2 ends before one check"},
    {"PlantSprite", "polls per plant, reports progress at its end; the sample input is one plant"},
    {"TreeMesh", "polls per plant, reports progress at its end; the sample input is one plant"},
    {"Turtle3D", "polls per module block, reports progress at its end; the sample word is short"},
    {"HullRock", "domain-independent: one convex hull of a bounded point count, no loop to poll"},
    {"Instance", "one linear pass over its input points"},
    {"MergePoints", "one linear pass over its input points"},
    {"ProjectToTerrain", "one linear pass over its input points"},
};

// Optional inputs left unconnected in the run cancelled at its first progress report, where the sample field
// would end the node's loop at once.
const std::map<std::string, std::string> kMidRunLeftOut = {
    {"WaterFlow", "sinks"},  // the bowl is above 0.5 everywhere: every cell a sink, all water gone at once
};

class EveryNode : public ::testing::TestWithParam<std::string> {
 protected:
  // The image codec (OpenImageIO, nodes/io/image_codec.h) is loaded on the first image read or written: a
  // dynamic load of some 250 libraries that no node can interrupt and that took up to 2.7 s on a loaded
  // machine. That is the program's start-up, not the node's cancellation latency: load it before timing.
  static void SetUpTestSuite() { image_codec(); }
};

TEST_P(EveryNode, StopsWithinTheBoundAtCostlyParameters) {
  const NodeType* type = NodeRegistry::instance().find(GetParam());
  ASSERT_NE(type, nullptr);
  OutputPolicy policy;
  policy.output_dir = test::scratch_dir("cancel-" + type->name);
  const auto values = test::sample_values(bowl(kSmall), policy);
  std::map<std::string, PortValue> inputs;
  for (const auto& in : type->inputs) {
    if (auto it = values.find(in.type); it != values.end())
      inputs[in.name] = it->second;
    else if (!in.optional)
      GTEST_SKIP() << "no producer of a " << in.name << " input yet";
  }
  bool exercised = false;
  for (const bool high : {true, false}) {
    const std::string label = type->name + (high ? ", parameters at their maxima" : ", parameters at their minima");
    const Timed t = run_timed(type->name, kSmall, at_end(*type, high), inputs, policy);
    expect_within_bound(label, t);
    exercised = exercised || t.cancelled_in_flight;
    // Refused up front for its work (nodes/common/work_bounds.h): the message names what to change.
    if (t.outcome.find("per-node ceiling") != std::string::npos ||
        t.outcome.find("exceeds the limit") != std::string::npos) {
      bool names_a_parameter = false;
      for (const auto& p : type->params)
        names_a_parameter = names_a_parameter || t.outcome.find(p.name) != std::string::npos;
      EXPECT_TRUE(names_a_parameter) << label << ": a work refusal must name the parameters to change: " << t.outcome;
      std::cout << label << ": refused up front for its work\n";
    }
  }
  // A node that finishes before the timed cancel (point-wise nodes on 33 x 33 take microseconds) is cancelled
  // at its first progress report instead, on a larger domain where its inputs allow (fields only), which must
  // stop it: it throws Cancelled, or returns at once (a simulation that converged on that step). A loop that
  // stopped polling would go on reporting progress and return a result.
  bool fields_only = true;
  for (const auto& in : type->inputs) fields_only = fields_only && (in.type == PortType::Heightfield || in.optional);
  std::map<std::string, PortValue> mid_inputs = inputs;
  if (fields_only)
    for (const auto& in : type->inputs)
      if (in.type == PortType::Heightfield) mid_inputs[in.name] = PortValue(bowl(kMidRun));
  if (auto left_out = kMidRunLeftOut.find(type->name); left_out != kMidRunLeftOut.end())
    mid_inputs.erase(left_out->second);
  std::map<std::string, ParamValue> mid_params;
  if (type->name == "ReadHeightfield") {  // a file to read
    const auto png = policy.output_dir / "read.png";
    HeightfieldWriteOptions o;
    o.format = HeightFormat::Png16;
    write_heightfield_file(*bowl(kMidRun), png, o);
    mid_params["path"] = png.string();
  }
  const MidRun mid =
      cancel_at_first_progress(type->name, fields_only ? kMidRun : kSmall, mid_params, mid_inputs, policy);
  std::cout << type->name << ", cancelled at its first progress report ("
            << (mid.reported ? std::to_string(mid.fraction) : std::string("none")) << "): " << mid.outcome << ", "
            << mid.reports_after << " reports after the cancel\n";
  if (mid.reported) {
    EXPECT_TRUE(mid.outcome == "cancelled" || (mid.outcome == "result" && mid.reports_after == 0))
        << type->name << " reported progress " << mid.fraction << ", was cancelled there, and went on ("
        << mid.reports_after << " more reports, then " << mid.outcome << ")";
    exercised = true;
  }
  const auto exempt = kNotExercised.find(type->name);
  std::cout << type->name << (exercised ? ": cancellation exercised" : ": cancellation not exercised") << "\n";
  if (exempt != kNotExercised.end())
    std::cout << "  listed as not exercisable: " << exempt->second << "\n";
  else
    EXPECT_TRUE(exercised) << type->name << " finished before the cancel and reported no progress before its end, so "
                           << "nothing here checks that it polls; make it report progress from its loops (or list it "
                           << "in kNotExercised with the reason)";
}

INSTANTIATE_TEST_SUITE_P(Registry, EveryNode, testing::ValuesIn(test::registered_type_names()), test::type_test_name);

// Issue #30, 1: droplets of 1e7 steps in a bowl (polled between droplet rounds, SIGINT took 94 s).
TEST(CancellationRepro, HydraulicErosionDropletsOfTenMillionSteps) {
  const Domain d = Domain::from_extent({0, 0}, {640, 640}, {65, 65});
  const Timed t =
      run_timed("HydraulicErosion", d, {{"lifetime", 1e5}, {"step_length", 0.01}}, {{"in", PortValue(bowl(d))}}, {});
  EXPECT_TRUE(t.cancelled_in_flight) << t.outcome;
  expect_within_bound("HydraulicErosion", t);
}

// 2: two million inner points, a search radius over the whole map, 1000 outlets (every growth iteration
// sorted all unused points; SIGINT took 109 s).
TEST(CancellationRepro, RiverNetworkOfTwoMillionPoints) {
  const Timed t = run_timed(
      "RiverNetwork", kSmall,
      {{"size", glm::dvec2(14000.0)}, {"density", 10000.0}, {"max_length", 1e6}, {"outlets", std::int64_t{1000}}}, {},
      {});
  expect_within_bound("RiverNetwork", t);
}

// 3: a low sun, tiny crowns on a plateau 1e6 m up: each query marched 1e9 steps (polled every 4096 points).
TEST(CancellationRepro, ShadePlacementMarchesFromUnderAHighPlateau) {
  auto casters = std::make_shared<Points>();
  auto candidates = std::make_shared<Points>();
  for (int k = 0; k < 2000; ++k) {
    casters->add({static_cast<float>(k % 50) * 6.0f, static_cast<float>(k / 50) * 8.0f, 1e6f});
    candidates->add({static_cast<float>(k % 40) * 8.0f, static_cast<float>(k / 40) * 6.0f, 0.0f});
  }
  const Timed t = run_timed("ShadePlacement", kSmall, {{"crown_radius", 0.01}, {"sun_elevation", 1.0}},
                            {{"in", PortValue(std::shared_ptr<const Points>(candidates))},
                             {"casters", PortValue(std::shared_ptr<const Points>(casters))}},
                            {});
  expect_within_bound("ShadePlacement", t);
}

// 4: a 1 x 1e7 m island rasterised on 65^2 (the locator's grid was 1 x 4096 buckets: O(4096^3) per lookup).
TEST(CancellationRepro, PolygonMapRasterOfAThinIsland) {
  const auto island = run_node("VoronoiIsland", kSmall, {{"size", glm::dvec2(1.0, 1e7)}});
  const Domain d = Domain::from_extent({0, 0}, {1.0, 1e7}, {65, 65});
  const auto start = Clock::now();
  const Timed t = run_timed("PolygonMapRaster", d, {}, {{"in", island.outputs.at(0)}}, {});
  expect_within_bound("PolygonMapRaster", t);
  EXPECT_EQ(t.outcome, "result");
  EXPECT_LT(Seconds(Clock::now() - start).count(), 0.5 * kSanitizerFactor) << "the lookups are no longer O(buckets)";
}

// Found by fuzz_graph_eval: cells of 10 km hold millions of candidates each, and the cell rows were polled per
// chunk of rows only.
TEST(CancellationRepro, ScatterRulesWithCellsOfTenKilometres) {
  const Domain d = Domain::from_extent({0, 0}, {12000, 12000}, {51, 51});
  expect_within_bound("ScatterRules",
                      run_timed("ScatterRules", d, {{"cell_size", 9999.99}}, {{"in", PortValue(bowl(d))}}, {}));
}

// Found by fuzz_graph_eval: one rock of 9855 points on its ellipsoid (sigma 0: all on the hull) refined 4 times, 5
// million triangles and seconds even without sanitizers, polled only between rocks.
TEST(CancellationRepro, RockSetOfFiveMillionTriangles) {
  const Timed t = run_timed("RockSet", kSmall,
                            {{"count", std::int64_t{1}},
                             {"points", std::int64_t{9855}},
                             {"subdivisions", std::int64_t{4}},
                             {"sigma", 0.0},
                             {"displacement", 999.999},
                             {"wavelength", 999.999}},
                            {}, {});
  EXPECT_TRUE(t.cancelled_in_flight) << t.outcome;
  expect_within_bound("RockSet", t);
}

// Simulations at legal but long settings: PipeErosion for 1e7 s, StreamPower for 1e10 yr in 1e5-yr steps.
TEST(CancellationRepro, LongSimulations) {
  const auto in = PortValue(bowl(kSmall));
  expect_within_bound("PipeErosion", run_timed("PipeErosion", kSmall, {{"duration", 1e7}}, {{"in", in}}, {}));
  expect_within_bound("StreamPower",
                      run_timed("StreamPower", kSmall, {{"duration", 1e10}, {"time_step", 1e5}}, {{"in", in}}, {}));
}

// Writers poll per block of instances and vertices while the file is built, and per 64 KiB while it is written
// (they polled nowhere before): a scene of a million instances and a mesh of a million vertices, cancelled at
// their first progress report past half way, stop within the bound and leave no file behind. (A cancel 100 ms after the
// start came after the glTF scene was written on a fast machine.)
TEST(CancellationRepro, WritersOfAMillionInstancesOrVertices) {
  OutputPolicy policy;
  policy.output_dir = test::scratch_dir("cancel-writers");
  const Domain grid = Domain::from_extent({0, 0}, {10230, 10230}, {1024, 1024});
  const auto mesh = run_node("HeightfieldToMesh", grid, {}, {{"in", PortValue(bowl(grid))}}).outputs.at(0);
  auto pts = std::make_shared<Points>();
  for (int k = 0; k < 1000000; ++k)
    pts->add({static_cast<float>(k % 1000) * 10.0f, static_cast<float>(k / 1000) * 10.0f, 100.0f}, k % 4);
  auto scene = std::make_shared<Scene>();
  scene->instances = pts;
  const auto plant = run_node("HeightfieldToMesh", kSmall, {}, {{"in", PortValue(bowl(kSmall))}}).outputs.at(0);
  for (int c = 0; c < 4; ++c) scene->classes[c] = SceneClass{"class_" + std::to_string(c), std::get<MeshPtr>(plant)};
  const auto scene_value = PortValue(ScenePtr(scene));
  struct Case {
    std::string type, path;
    std::map<std::string, ParamValue> params;
    std::map<std::string, PortValue> inputs;
  };
  const Case cases[] = {
      {"WriteScene", "scene.gltf", {}, {{"in", scene_value}}},
      {"WriteScene", "scene.glb", {}, {{"in", scene_value}, {"terrain", mesh}}},
      {"WriteMesh", "terrain.obj", {}, {{"in", mesh}}},
      {"WriteMesh", "terrain.ply", {{"binary", false}}, {{"in", mesh}}},
      {"WriteMesh", "terrain.gltf", {}, {{"in", mesh}}},
  };
  for (const Case& c : cases) {
    auto params = c.params;
    params["path"] = c.path;
    const Timed t = run_timed(c.type, kSmall, params, c.inputs, policy, std::chrono::seconds(60), 0.5);
    const std::string label = c.type + " to " + c.path;
    EXPECT_TRUE(t.cancelled_in_flight) << label << ": " << t.outcome;
    EXPECT_EQ(t.outcome, "cancelled") << label;
    expect_within_bound(label, t);
    EXPECT_FALSE(std::filesystem::exists(policy.output_dir / c.path)) << label;
  }
}

}  // namespace
}  // namespace orogen
