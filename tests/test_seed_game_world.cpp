// graphs/game_world.json, the 3D game world of H. Zaiz (2022), "Procedural Generation of 3D Game Worlds",
// as one graph, checked against what that report promised, on the graph's real outputs at a reduced
// resolution:
//  - the L-system plants have the symbol counts of its grammars (rule 4.19 after 3 iterations: 322
//    symbols; rule 4.20 after 4: 1551), and the counts follow the grammar's recurrences at every iteration;
//  - the particle hydraulic erosion conserves volume: what it eroded equals what it deposited plus what the
//    droplets carried off the map, and the terrain lost exactly what was carried off; thermal erosion
//    conserves volume exactly.
//  - the fBm is 3 Perlin + 4 simplex octaves at lacunarity 1.7 and persistence 0.4.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "evaluator/evaluator.h"
#include "graph/graph_file.h"
#include "graph/heightfield.h"
#include "graph/module_string.h"
#include "graph/points.h"
#include "graph/report.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

namespace fs = std::filesystem;

const fs::path kGraph = test::source_dir() / "graphs" / "game_world.json";

Graph load() {
  const auto loaded = load_graph_file(kGraph);
  EXPECT_TRUE(loaded.ok()) << loaded.error_text();
  return *loaded.graph;
}

struct Evaluated {
  Graph graph;
  EvalResult result;
  template <class T>
  std::shared_ptr<const T> get(const std::string& node, const std::string& port = "out") const {
    return std::get<std::shared_ptr<const T>>(result.output(node, port, graph));
  }
};

// The graph on its own 2048 m square at `samples` x `samples` (the CLI's --resolution).
Evaluated evaluate(Graph graph, int samples, std::vector<std::string> nodes) {
  Evaluated e{std::move(graph), {}};
  Evaluator evaluator;
  EvalRequest request;
  request.domain = Domain::from_extent({0, 0}, {2048, 2048}, {samples, samples});
  request.nodes = std::move(nodes);
  e.result = evaluator.evaluate(e.graph, request);
  EXPECT_TRUE(e.result.ok());
  for (const auto& [id, report] : e.result.nodes)
    if (!report.message.empty()) ADD_FAILURE() << id << ": " << report.message;
  return e;
}

struct Counts {
  long x = 0, f = 0, other = 0;
  long total() const { return x + f + other; }
};

Counts count(const ModuleString& w) {
  Counts c;
  for (char s : w.symbols) {
    if (s == 'X')
      ++c.x;
    else if (s == 'F')
      ++c.f;
    else
      ++c.other;
  }
  return c;
}

// Symbol counts after n parallel rewritings of X with F -> FF and X -> a successor holding sx X, sf F and
// so other symbols: x' = sx x, f' = 2 f + sf x, other' = other + so x.
Counts recurrence(int n, long sx, long sf, long so) {
  Counts c{1, 0, 0};
  for (int k = 0; k < n; ++k) c = {sx * c.x, 2 * c.f + sf * c.x, c.other + so * c.x};
  return c;
}

TEST(SeedGameWorld, LSystemPlantsHaveTheGrammarsSymbolCounts) {
  const auto e = evaluate(load(), 65, {"plant_a", "plant_b"});
  const auto a = e.get<ModuleString>("plant_a");
  const auto b = e.get<ModuleString>("plant_b");
  ASSERT_TRUE(a && b);
  // The report's figures: rule 4.19, 3 iterations; rule 4.20, 4 iterations.
  EXPECT_EQ(a->size(), 322u);
  EXPECT_EQ(b->size(), 1551u);
  const Counts ca = count(*a), cb = count(*b);
  EXPECT_EQ(ca.x, 27);
  EXPECT_EQ(ca.f, 152);
  EXPECT_EQ(cb.x, 256);
  EXPECT_EQ(cb.f, 360);

  // Every iteration count of the graph's own grammars follows the recurrence (4.19: X -> 3 X, 8 F, 11
  // others; 4.20: X -> 4 X, 3 F, 11 others).
  for (int n = 0; n <= 5; ++n) {
    Graph g = load();
    g.set_param("plant_a", "iterations", ParamValue(static_cast<std::int64_t>(n)));
    g.set_param("plant_b", "iterations", ParamValue(static_cast<std::int64_t>(n)));
    const auto en = evaluate(std::move(g), 65, {"plant_a", "plant_b"});
    const Counts got_a = count(*en.get<ModuleString>("plant_a")), got_b = count(*en.get<ModuleString>("plant_b"));
    const Counts want_a = recurrence(n, 3, 8, 11), want_b = recurrence(n, 4, 3, 11);
    EXPECT_EQ(got_a.x, want_a.x) << "4.19, n = " << n;
    EXPECT_EQ(got_a.f, want_a.f) << "4.19, n = " << n;
    EXPECT_EQ(got_a.other, want_a.other) << "4.19, n = " << n;
    EXPECT_EQ(got_b.x, want_b.x) << "4.20, n = " << n;
    EXPECT_EQ(got_b.f, want_b.f) << "4.20, n = " << n;
    EXPECT_EQ(got_b.other, want_b.other) << "4.20, n = " << n;
  }
}

double volume(const Heightfield& h) {
  double s = 0;
  for (float v : h.data) s += v;
  return s * h.domain.spacing.x * h.domain.spacing.y;
}

TEST(SeedGameWorld, HydraulicErosionConservesVolume) {
  const auto e = evaluate(load(), 129, {"raised", "hydraulic"});
  const auto in = e.get<Heightfield>("raised");
  const auto out = e.get<Heightfield>("hydraulic");
  const auto eroded_map = e.get<Heightfield>("hydraulic", "erosion");
  const auto deposited_map = e.get<Heightfield>("hydraulic", "deposition");
  const auto report = e.get<Report>("hydraulic", "report");
  ASSERT_TRUE(in && out && eroded_map && deposited_map && report);
  const auto r = nlohmann::json::parse(report->json);
  const double eroded = r["eroded"], deposited = r["deposited"], carried_off = r["carried_off"];
  // Zaiz 2022's 30 K droplets over the map.
  EXPECT_NEAR(r["droplets"].get<double>(), 30000.0, 300.0);
  ASSERT_GT(eroded, 1000.0);  // m^3: the erosion did something
  EXPECT_GT(deposited, 0.5 * eroded);
  EXPECT_GE(carried_off, 0.0);

  // The droplets' ledger: every cubic metre eroded was deposited or carried off the map.
  const double tol = 1e-4 * eroded;
  EXPECT_NEAR(eroded, deposited + carried_off, tol);
  // The terrain agrees with the ledger: it lost exactly what was carried off (measured on the heights, not
  // on the droplets)...
  const double lost = volume(*in) - volume(*out);
  EXPECT_NEAR(lost, carried_off, 2e-3 * eroded + 1.0) << "eroded " << eroded << " deposited " << deposited;
  // ...and so do the wear and deposit maps (net per cell, so at most the droplets' gross figures).
  const double wear = volume(*eroded_map), deposits = volume(*deposited_map);
  EXPECT_NEAR(wear - deposits, carried_off, 2e-3 * eroded + 1.0);
  EXPECT_LE(wear, eroded * (1 + 1e-4));
  EXPECT_LE(deposits, deposited * (1 + 1e-4));
  for (std::size_t k = 0; k < in->data.size(); ++k) {
    ASSERT_GE(eroded_map->data[k], 0.0f);
    ASSERT_GE(deposited_map->data[k], 0.0f);
  }
}

TEST(SeedGameWorld, ThermalErosionConservesVolumeAndFlattensTheSteepest) {
  const auto e = evaluate(load(), 129, {"hydraulic", "thermal"});
  const auto in = e.get<Heightfield>("hydraulic");
  const auto out = e.get<Heightfield>("thermal");
  const auto moved = e.get<Heightfield>("thermal", "erosion");
  ASSERT_TRUE(in && out && moved);
  EXPECT_GT(volume(*moved), 100.0);  // material slid
  EXPECT_NEAR(volume(*out), volume(*in), 1e-6 * std::abs(volume(*in)) + 1e-3 * volume(*moved));
}

TEST(SeedGameWorld, FbmIsThreePerlinAndFourSimplexOctavesAtLacunarity17AndPersistence04) {
  const Graph g = load();
  auto num = [&](const char* node, const char* name) { return std::get<double>(g.param(node, name)); };
  auto integer = [&](const char* node, const char* name) { return std::get<std::int64_t>(g.param(node, name)); };
  EXPECT_EQ(std::get<std::string>(g.param("fbm_perlin", "basis")), "perlin");
  EXPECT_EQ(std::get<std::string>(g.param("fbm_simplex", "basis")), "simplex");
  EXPECT_EQ(integer("fbm_perlin", "octaves"), 3);
  EXPECT_EQ(integer("fbm_simplex", "octaves"), 4);
  for (const char* node : {"fbm_perlin", "fbm_simplex"}) {
    EXPECT_DOUBLE_EQ(num(node, "lacunarity"), 1.7);
    EXPECT_DOUBLE_EQ(num(node, "gain"), 0.4);
  }
  // The simplex octaves continue the Perlin ones: octave 3 of the whole sum, at 1.7^3 the frequency and
  // 0.4^3 the weight. Each FBM node divides by the sum of its own weights, so the amplitudes carry them.
  const double s3 = (1 - std::pow(0.4, 3)) / 0.6, s4 = (1 - std::pow(0.4, 4)) / 0.6;
  EXPECT_NEAR(num("fbm_perlin", "feature_size") / num("fbm_simplex", "feature_size"), std::pow(1.7, 3), 1e-3);
  EXPECT_NEAR(num("fbm_simplex", "amplitude") / num("fbm_perlin", "amplitude"), std::pow(0.4, 3) * s4 / s3, 1e-4);

  // The sum is a terrain with sea and land, as Zaiz 2022's color map shows.
  const auto e = evaluate(g, 129, {"raised", "color_map", "placed"});
  const auto h = e.get<Heightfield>("raised");
  const auto water = std::count_if(h->data.begin(), h->data.end(), [](float v) { return v < 0; });
  const double share = static_cast<double>(water) / static_cast<double>(h->data.size());
  EXPECT_GT(share, 0.05);
  EXPECT_LT(share, 0.6);
  // Plants scattered on land only.
  const auto placed = e.get<Points>("placed");
  ASSERT_GT(placed->size(), 100u);
  for (const auto& p : placed->position) EXPECT_GT(p.z, 0.0f);
}

}  // namespace
}  // namespace orogen
