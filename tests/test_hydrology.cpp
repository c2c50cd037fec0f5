// The hydrology nodes: filling modes, rivers, lakes, water flow, drainage metrics, curves files, and the node
// contract (thread-count determinism, resolution convergence, cache keys, documentation).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "field_ops_fixtures.h"
#include "graph/registry.h"
#include "evaluator/value_serialization.h"
#include "graph/report.h"
#include "nodes/hydrology/channels.h"
#include "nodes/hydrology/drainage_metrics.h"
#include "nodes/hydrology/flow_routing.h"
#include "nodes/io/curves_file.h"
#include "support/key_checks.h"
#include "support/run_process.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

using hydrology::FlowGrid;
using test::field_from;

// Hilly terrain with closed depressions, tilted toward +x.
double bumpy(double x, double y) {
  return 60.0 * std::sin(x / 210.0) * std::cos(y / 170.0) + 35.0 * std::sin((x + 2 * y) / 390.0) - 0.04 * x +
         8.0 * test::hash01(static_cast<std::int64_t>(std::floor(x / 40.0)),
                            static_cast<std::int64_t>(std::floor(y / 40.0)));
}

HeightfieldPtr bumpy_field(const Domain& d) { return field_from(d, bumpy); }

Domain small_domain() { return Domain::from_extent({0, 0}, {2550, 2550}, {256, 256}); }  // 10 m

PortValue pv(HeightfieldPtr h) { return PortValue(std::move(h)); }

// ---- FillDepressions ---------------------------------------------------------------------------------------

TEST(FillDepressionsNode, FillsWithLakesAndCarvesDeepPitsKeepingShallowOnes) {
  // Two bowls in a plane sloping to +x: a shallow one (2 m) and a deep one (30 m).
  const Domain d = Domain::from_extent({0, 0}, {1270, 630}, {128, 64});
  auto bowls = [](double x, double y) {
    const double shallow = std::max(0.0, 2.0 * (1.0 - std::hypot(x - 300, y - 300) / 120.0));
    const double deep = std::max(0.0, 30.0 * (1.0 - std::hypot(x - 900, y - 300) / 150.0));
    return 100.0 - 0.005 * x - shallow - deep;
  };
  const auto in = field_from(d, bowls);
  const NodeRun fill = run_node("FillDepressions", d, {}, {{"in", pv(in)}});
  const auto out = fill.get<Heightfield>(0), depth = fill.get<Heightfield>(1), id = fill.get<Heightfield>(2);
  std::set<float> ids(id->data.begin(), id->data.end());
  EXPECT_EQ(ids, (std::set<float>{0.0f, 1.0f, 2.0f}));
  for (std::size_t c = 0; c < in->data.size(); ++c) {
    ASSERT_GE(out->data[c], in->data[c]);
    ASSERT_GE(depth->data[c], 0.0f);
    if (id->data[c] > 0) {
      ASSERT_NEAR(out->data[c], in->data[c] + depth->data[c], 1e-3);
    }
  }
  const NodeRun carve =
      run_node("FillDepressions", d, {{"mode", std::string("carve")}, {"max_depth", 5.0}}, {{"in", pv(in)}});
  const auto cout = carve.get<Heightfield>(0), cid = carve.get<Heightfield>(2);
  std::set<float> cids(cid->data.begin(), cid->data.end());
  EXPECT_EQ(cids, (std::set<float>{0.0f, 1.0f})) << "the shallow bowl is kept as a lake, the deep one carved";
  int lowered = 0;
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) {
      const float a = in->at(i, j), b = cout->at(i, j);
      if (cid->at(i, j) > 0) {
        ASSERT_GE(b, a);  // the kept lake is filled
      } else if (d.x(i) > 600) {
        ASSERT_LE(b, a + 1e-3f);  // around the deep bowl the terrain is only cut
        lowered += b < a;
      }
    }
  EXPECT_GT(lowered, 0);
  // Every cell drains after carving with epsilon.
  const hydrology::D8Flow f = hydrology::d8_flow(FlowGrid::of(d), cout->data);
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(f.receiver.size()); ++c) {
    std::int32_t x = c;
    while (f.receiver[x] != x) x = f.receiver[x];
    const int i = x % d.width(), j = x / d.width();
    ASSERT_TRUE(i == 0 || j == 0 || i == d.width() - 1 || j == d.height() - 1);
  }
}

// ---- FlowAccumulation, FlowDirection, Watersheds -----------------------------------------------------------

TEST(FlowAccumulationNode, RainfallWeightsAndMapsInRange) {
  const Domain d = small_domain();
  const auto in = bumpy_field(d);
  auto two = std::make_shared<Heightfield>(d, 2.0f);
  for (const char* m : {"d8", "dinf", "mfd"}) {
    SCOPED_TRACE(m);
    const NodeRun a = run_node("FlowAccumulation", d, {{"method", std::string(m)}}, {{"in", pv(in)}});
    const NodeRun b =
        run_node("FlowAccumulation", d, {{"method", std::string(m)}}, {{"in", pv(in)}, {"rainfall_weight", pv(two)}});
    const auto acc = a.get<Heightfield>(0), acc2 = b.get<Heightfield>(0), flow = a.get<Heightfield>(1),
               wet = a.get<Heightfield>(2);
    for (std::size_t c = 0; c < acc->data.size(); ++c) {
      ASSERT_NEAR(acc2->data[c], 2.0f * acc->data[c], 1e-5f * acc2->data[c]);
      ASSERT_GE(acc->data[c], 100.0f * (1 - 1e-6f));  // at least the cell's own 10 m x 10 m
      ASSERT_GE(flow->data[c], 0.0f);
      ASSERT_LE(flow->data[c], 1.0f);
      ASSERT_TRUE(std::isfinite(wet->data[c]));
    }
    EXPECT_EQ(*std::max_element(flow->data.begin(), flow->data.end()), 1.0f);
  }
}

TEST(FlowDirectionNode, UnitVectorsPointDownhill) {
  const Domain d = small_domain();
  const auto in =
      field_from(d, [](double x, double y) { return 60.0 * std::sin(x / 210.0) * std::cos(y / 170.0) + 0.05 * x; });
  for (const char* m : {"d8", "dinf", "mfd"}) {
    const NodeRun r = run_node("FlowDirection", d, {{"method", std::string(m)}, {"fill", false}}, {{"in", pv(in)}});
    const auto angle = r.get<Heightfield>(0), dx = r.get<Heightfield>(1), dy = r.get<Heightfield>(2);
    int checked = 0;
    for (int j = 1; j < d.height() - 1; ++j)
      for (int i = 1; i < d.width() - 1; ++i) {
        if (angle->at(i, j) < 0) continue;
        ASSERT_NEAR(std::hypot(dx->at(i, j), dy->at(i, j)), 1.0, 1e-5);
        ASSERT_NEAR(std::atan2(dy->at(i, j), dx->at(i, j)) * 180 / M_PI + (dy->at(i, j) < 0 ? 360 : 0), angle->at(i, j),
                    1e-2);
        // The ground a cell further along the flow is lower (bilinear, smooth terrain).
        const double ahead = in->sample_world(d.x(i) + 10 * dx->at(i, j), d.y(j) + 10 * dy->at(i, j));
        EXPECT_LT(ahead, in->at(i, j) + 0.5) << m << " " << i << "," << j;
        ++checked;
      }
    EXPECT_GT(checked, d.width() * d.height() / 2);
  }
}

TEST(WatershedsNode, BasinsPartitionTheAreaAndSmallOnesAreDropped) {
  const Domain d = small_domain();
  const auto in = bumpy_field(d);
  const NodeRun all = run_node("Watersheds", d, {}, {{"in", pv(in)}});
  const auto id = all.get<Heightfield>(0), area = all.get<Heightfield>(1);
  std::map<float, double> cells;
  for (std::size_t c = 0; c < id->data.size(); ++c) cells[id->data[c]] += 100.0;
  EXPECT_EQ(cells.count(0.0f), 0u);
  double previous = 1e300;
  for (const auto& [k, a] : cells) {
    EXPECT_LE(a, previous) << "numbered by decreasing area";
    previous = a;
  }
  for (std::size_t c = 0; c < id->data.size(); ++c)
    ASSERT_NEAR(area->data[c], cells[id->data[c]], 1e-3 * area->data[c]);
  const double min_area = 50000.0;
  const NodeRun big = run_node("Watersheds", d, {{"min_area", min_area}}, {{"in", pv(in)}});
  const auto id2 = big.get<Heightfield>(0);
  for (std::size_t c = 0; c < id2->data.size(); ++c) {
    if (area->data[c] < min_area)
      ASSERT_EQ(id2->data[c], 0.0f);
    else
      ASSERT_GT(id2->data[c], 0.0f);
  }
}

// ---- RiverExtract -----------------------------------------------------------------------------------------

struct Rivers {
  CurvesPtr curves;
  HeightfieldPtr mask;
};

Rivers rivers(const Domain& d, const HeightfieldPtr& in, bool split, double threshold = 4e4) {
  const NodeRun r =
      run_node("RiverExtract", d, {{"threshold", threshold}, {"split_at_lakes", split}, {"smoothing", std::int64_t{2}}},
               {{"in", pv(in)}});
  return {r.get<Curves>(0), r.get<Heightfield>(1)};
}

TEST(RiverExtractNode, ReachesRunDownhillJoinLargerReachesAndWidenDownstream) {
  const Domain d = small_domain();
  const auto in = bumpy_field(d);
  const Rivers r = rivers(d, in, false);
  const Curves& cs = *r.curves;
  cs.check_consistent();
  ASSERT_GT(cs.size(), 10u);
  const glm::dvec2 lo = d.min_corner(), hi = d.max_corner();
  std::map<int, std::vector<int>> children;
  for (std::size_t k = 0; k < cs.size(); ++k) {
    const Curve& c = cs.curves[k];
    ASSERT_GE(c.points.size(), 2u);
    for (std::size_t v = 1; v < c.points.size(); ++v) {
      ASSERT_LE(c.points[v].z, c.points[v - 1].z) << "reach " << k << " climbs at vertex " << v;
      ASSERT_GE(c.width[v], c.width[v - 1]) << "reach " << k;
      ASSERT_GE(c.attributes.at("discharge")[v], c.attributes.at("discharge")[v - 1]);
    }
    if (c.parent < 0) {
      const auto& e = c.points.back();
      EXPECT_TRUE(std::abs(e.x - lo.x) < 1e-3 || std::abs(e.y - lo.y) < 1e-3 || std::abs(e.x - hi.x) < 1e-3 ||
                  std::abs(e.y - hi.y) < 1e-3)
          << "a root reach ends on the border";
    } else {
      ASSERT_LT(c.parent, static_cast<int>(k));
      const Curve& p = cs.curves[static_cast<std::size_t>(c.parent)];
      EXPECT_EQ(c.points.back(), p.points.front()) << "reach " << k << " ends where its parent starts";
      EXPECT_LE(c.width.back(), p.width.front() * (1 + 1e-6f));
      children[c.parent].push_back(static_cast<int>(k));
    }
  }
  // Strahler: a reach's order is its highest child order, plus one if two children share it; sources are 1.
  for (std::size_t k = 0; k < cs.size(); ++k) {
    const int order = static_cast<int>(cs.curves[k].attributes.at("order").front());
    const auto it = children.find(static_cast<int>(k));
    if (it == children.end()) {
      EXPECT_EQ(order, 1) << "reach " << k;
      continue;
    }
    EXPECT_GE(it->second.size(), 2u) << "a reach starts at a confluence";
    int best = 0, ties = 0;
    for (int ch : it->second) {
      const int o = static_cast<int>(cs.curves[static_cast<std::size_t>(ch)].attributes.at("order").front());
      if (o > best)
        best = o, ties = 1;
      else if (o == best)
        ++ties;
    }
    EXPECT_EQ(order, ties >= 2 ? best + 1 : best) << "reach " << k;
  }
}

TEST(RiverExtractNode, LakesAreLeftWithoutLinesAndTheMaskFollowsTheWidth) {
  const Domain d = small_domain();
  const auto in = bumpy_field(d);
  const Rivers r = rivers(d, in, true);
  const NodeRun lakes = run_node("Lakes", d, {}, {{"in", pv(in)}});
  const auto depth = lakes.get<Heightfield>(1);
  ASSERT_GT(*std::max_element(depth->data.begin(), depth->data.end()), 0.5f);
  ASSERT_GT(r.curves->size(), 10u);
  // Unsmoothed: no interior vertex in a lake.
  const NodeRun raw =
      run_node("RiverExtract", d, {{"threshold", 4e4}, {"smoothing", std::int64_t{0}}}, {{"in", pv(in)}});
  int inner = 0;
  for (const Curve& c : raw.get<Curves>(0)->curves)
    for (std::size_t v = 1; v + 1 < c.points.size(); ++v) {
      const glm::dvec2 s = d.to_sample({c.points[v].x, c.points[v].y});
      ASSERT_EQ(depth->at(static_cast<int>(std::lround(s.x)), static_cast<int>(std::lround(s.y))), 0.0f);
      ++inner;
    }
  EXPECT_GT(inner, 100);
  // Mask: 1 on wide reaches' vertices, 0 far from every reach.
  const Rivers wide = [&] {
    const NodeRun w =
        run_node("RiverExtract", d, {{"threshold", 4e4}, {"width_coefficient", 30.0}, {"smoothing", std::int64_t{0}}},
                 {{"in", pv(in)}});
    return Rivers{w.get<Curves>(0), w.get<Heightfield>(1)};
  }();
  for (const Curve& c : wide.curves->curves)
    for (std::size_t v = 0; v < c.points.size(); ++v) {
      if (c.width[v] < 25.0f) continue;
      const glm::dvec2 s = d.to_sample({c.points[v].x, c.points[v].y});
      ASSERT_EQ(wide.mask->at(static_cast<int>(std::lround(s.x)), static_cast<int>(std::lround(s.y))), 1.0f);
    }
  double mask_area = 0.0, line_area = 0.0;
  for (float m : wide.mask->data) mask_area += m * 100.0;
  for (const Curve& c : wide.curves->curves)
    for (std::size_t v = 0; v + 1 < c.points.size(); ++v)
      line_area +=
          0.5 * (c.width[v] + c.width[v + 1]) * glm::length(glm::vec2(c.points[v + 1]) - glm::vec2(c.points[v]));
  EXPECT_GT(mask_area, 0.5 * line_area);
  EXPECT_LT(mask_area, 1.5 * line_area);
}

// ---- Lakes and FloodFill ----------------------------------------------------------------------------------

TEST(FloodFillNode, LakeIsFlatAndBoundedByHigherGroundOrTheSpill) {
  const Domain d = small_domain();
  const auto in = bumpy_field(d);
  // Seed at the deepest point of the largest depression.
  const NodeRun lk = run_node("Lakes", d, {}, {{"in", pv(in)}});
  const auto depth = lk.get<Heightfield>(1), surface = lk.get<Heightfield>(0);
  const std::size_t deepest =
      static_cast<std::size_t>(std::max_element(depth->data.begin(), depth->data.end()) - depth->data.begin());
  const int si = static_cast<int>(deepest % 256), sj = static_cast<int>(deepest / 256);
  for (bool spill : {true, false}) {
    const double level = spill ? surface->data[deepest] : in->data[deepest] + 0.5 * depth->data[deepest];
    const NodeRun r = run_node("FloodFill", d,
                               {{"position", glm::dvec2(d.x(si), d.y(sj))},
                                {"level_mode", std::string(spill ? "spill" : "level")},
                                {"level", level}},
                               {{"in", pv(in)}});
    const auto out = r.get<Heightfield>(0), dep = r.get<Heightfield>(1), mask = r.get<Heightfield>(2);
    int wet = 0;
    for (int j = 0; j < 256; ++j)
      for (int i = 0; i < 256; ++i) {
        if (mask->at(i, j) == 0.0f) {
          ASSERT_EQ(out->at(i, j), in->at(i, j));
          continue;
        }
        ++wet;
        ASSERT_EQ(out->at(i, j), static_cast<float>(level)) << "flat surface";
        ASSERT_GT(dep->at(i, j), 0.0f);
        for (int k = 0; k < 8; ++k) {
          const int ii = i + hydrology::kDi[k], jj = j + hydrology::kDj[k];
          if (ii < 0 || jj < 0 || ii >= 256 || jj >= 256) continue;
          if (mask->at(ii, jj) == 0.0f) {
            ASSERT_GE(in->at(ii, jj), static_cast<float>(level)) << "bounded by higher ground";
          }
        }
      }
    EXPECT_GT(wet, 10);
    if (spill) {
      // The spill level lets the lake match the filled depression exactly.
      for (std::size_t c = 0; c < mask->data.size(); ++c)
        if (mask->data[c] > 0) {
          ASSERT_EQ(surface->data[c], out->data[c]);
        }
    }
  }
}

// ---- WaterFlow --------------------------------------------------------------------------------------------

TEST(WaterFlowNode, ConservesWaterExceptAtTheBorderAndSinks) {
  const Domain d = Domain::from_extent({0, 0}, {1270, 1270}, {128, 128});
  const auto in = bumpy_field(d);
  auto sinks = std::make_shared<Heightfield>(d, 0.0f);
  for (int j = 60; j < 70; ++j)
    for (int i = 60; i < 70; ++i) sinks->at(i, j) = 1.0f;
  const NodeRun r =
      run_node("WaterFlow", d, {{"rainfall", 80.0}, {"infiltration", 20.0}, {"max_iterations", std::int64_t{300}}},
               {{"in", pv(in)}, {"sinks", pv(sinks)}});
  const auto depth = r.get<Heightfield>(0);
  const auto rep = nlohmann::json::parse(r.get<Report>(2)->json);
  const double rain = rep["rain_m3"], stored = rep["stored_m3"], border = rep["border_outflow_m3"],
               sink = rep["sink_inflow_m3"];
  EXPECT_NEAR(rain, 0.06 * 1270.0 * 1270.0 / (127.0 * 127.0) * 128 * 128, 1e-6 * rain);
  EXPECT_NEAR(rain, stored + border + sink, 1e-9 * rain);
  EXPECT_GT(border, 0.0);
  EXPECT_GT(sink, 0.0);
  double s = 0.0;
  for (float v : depth->data) {
    ASSERT_GE(v, 0.0f);
    s += v * 100.0;
  }
  EXPECT_NEAR(s, stored, 1e-5 * stored);
  EXPECT_GT(static_cast<int>(rep["iterations"]), 5);
}

TEST(WaterFlowNode, NeverMovesWaterUphillAndPoolsFlat) {
  // A closed bowl (rim higher than any water) with a high plateau step inside.
  const Domain d = Domain::from_extent({0, 0}, {630, 630}, {64, 64});
  auto bowl = [](double x, double y) {
    const double r = std::hypot(x - 315, y - 315);
    return r > 280 ? 50.0 : 0.002 * r * r + (x > 400 && std::abs(y - 315) < 60 ? 20.0 : 0.0);
  };
  const auto in = field_from(d, bowl);
  // One iteration: a plateau cell receives nothing from lower surfaces.
  const NodeRun one =
      run_node("WaterFlow", d, {{"rainfall", 30.0}, {"infiltration", 0.0}, {"max_iterations", std::int64_t{1}}},
               {{"in", pv(in)}});
  const auto w1 = one.get<Heightfield>(0);
  for (int j = 1; j < 63; ++j)
    for (int i = 1; i < 63; ++i) {
      double higher_neighbour_surface = -1e9;
      for (int k = 0; k < 8; ++k)
        higher_neighbour_surface =
            std::max<double>(higher_neighbour_surface, in->at(i + hydrology::kDi[k], j + hydrology::kDj[k]) + 0.03);
      if (higher_neighbour_surface < in->at(i, j)) {
        ASSERT_LE(w1->at(i, j), 0.03f + 1e-7f) << "a peak gained water";
      }
    }
  // To convergence: the pooled water has a flat surface and nothing is lost (no border water: rim is dry).
  const NodeRun all = run_node(
      "WaterFlow", d,
      {{"rainfall", 300.0}, {"infiltration", 0.0}, {"threshold", 1e-6}, {"max_iterations", std::int64_t{20000}}},
      {{"in", pv(in)}});
  const auto w = all.get<Heightfield>(0);
  const auto rep = nlohmann::json::parse(all.get<Report>(2)->json);
  EXPECT_NEAR(static_cast<double>(rep["rain_m3"]),
              static_cast<double>(rep["stored_m3"]) + static_cast<double>(rep["border_outflow_m3"]),
              1e-9 * static_cast<double>(rep["rain_m3"]));
  double lo = 1e9, hi = -1e9;
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i)
      if (w->at(i, j) > 0.5f) {
        lo = std::min(lo, static_cast<double>(in->at(i, j) + w->at(i, j)));
        hi = std::max(hi, static_cast<double>(in->at(i, j) + w->at(i, j)));
      }
  ASSERT_LT(lo, hi + 1);
  EXPECT_LT(hi - lo, 0.05) << "pooled water is level";
}

// ---- DrainageMetrics ----------------------------------------------------------------------------------------

// D8 flow from explicit receivers (cell -> neighbour cell or itself).
hydrology::D8Flow flow_from(const FlowGrid& g, const std::vector<std::int32_t>& rec) {
  hydrology::D8Flow f;
  f.receiver = rec;
  f.direction.assign(rec.size(), hydrology::kNoDirection);
  f.donors.assign(rec.size(), 0);
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(rec.size()); ++c) {
    if (rec[c] == c) continue;
    for (int k = 0; k < 8; ++k)
      if (c + g.offset(k) == rec[c]) {
        f.direction[c] = static_cast<std::uint8_t>(k);
        f.donors[rec[c]] |= static_cast<std::uint8_t>(1u << hydrology::opposite(k));
      }
  }
  return f;
}

TEST(DrainageMetrics, BinaryTreeOfKnownStrahlerOrders) {
  // j down the page:      a . b . . . c . d      (order 1)
  //                        . e . . . . . f .      (order 2 from here)
  //                        . . g . . . h . .
  //                        . . . i . k . . .
  //                        . . . . m . . . .      (order 3)
  //                        . . . . n . . . .
  //                        . . . . o . . . .      (outlet on the border)
  const FlowGrid g(9, 7, 10.0, 10.0);
  std::vector<std::int32_t> rec(g.size());
  std::iota(rec.begin(), rec.end(), 0);
  auto link = [&](int i, int j, int ri, int rj) { rec[g.index(i, j)] = g.index(ri, rj); };
  link(0, 0, 1, 1), link(2, 0, 1, 1), link(6, 0, 7, 1), link(8, 0, 7, 1);
  link(1, 1, 2, 2), link(7, 1, 6, 2), link(2, 2, 3, 3), link(6, 2, 5, 3), link(3, 3, 4, 4), link(5, 3, 4, 4);
  link(4, 4, 4, 5), link(4, 5, 4, 6);
  const auto f = flow_from(g, rec);
  const auto stack = hydrology::stack_order(g, f);
  std::vector<std::uint8_t> channel(g.size(), 0);
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(g.size()); ++c) channel[c] = rec[c] != c || f.donors[c];
  std::vector<float> z(g.size(), 0.0f);
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(g.size()); ++c) z[c] = static_cast<float>(100 - 10 * g.row(c));
  const auto area = hydrology::accumulate_d8(g, f);
  const auto m = hydrology::network_metrics(g, f, stack, channel, area, z);
  auto order = [&](int i, int j) { return m.order[g.index(i, j)]; };
  for (auto [i, j] : {std::pair{0, 0}, {2, 0}, {6, 0}, {8, 0}}) EXPECT_EQ(order(i, j), 1);
  for (auto [i, j] : {std::pair{1, 1}, {7, 1}, {2, 2}, {6, 2}, {3, 3}, {5, 3}}) EXPECT_EQ(order(i, j), 2);
  for (auto [i, j] : {std::pair{4, 4}, {4, 5}, {4, 6}}) EXPECT_EQ(order(i, j), 3);
  EXPECT_EQ(order(4, 0), 0);
  EXPECT_EQ(m.max_order, 3);
  EXPECT_EQ(m.stream_counts, (std::vector<int>{4, 2, 1}));
  EXPECT_NEAR(m.bifurcation_ratio, 2.0, 1e-12);
  const double diag = std::hypot(10.0, 10.0);
  ASSERT_EQ(m.mean_stream_length.size(), 3u);
  EXPECT_NEAR(m.mean_stream_length[0], diag, 1e-9);
  EXPECT_NEAR(m.mean_stream_length[1], 3 * diag, 1e-9);
  EXPECT_NEAR(m.mean_stream_length[2], 20.0, 1e-9);
  // Reaches: 4 sources to the two confluences, two order-2 reaches to m, one order-3 reach to the outlet.
  const auto so = hydrology::strahler_orders(g, f, stack, channel);
  const auto reaches = hydrology::extract_reaches(g, f, stack, channel, so);
  ASSERT_EQ(reaches.size(), 7u);
  EXPECT_EQ(reaches[0].order, 3);
  EXPECT_EQ(reaches[0].parent, -1);
  EXPECT_EQ(reaches[0].cells.size(), 3u);
}

TEST(DrainageMetrics, PlanarRampHasParallelFirstOrderStreams) {
  const Domain d = Domain::from_extent({0, 0}, {1270, 630}, {128, 64});
  const auto in = field_from(d, [](double x, double) { return 200.0 - 0.1 * x; });
  const auto r = hydrology::drainage_metrics(*in, 1000.0);
  EXPECT_EQ(r.pits_per_million, 0.0);
  EXPECT_EQ(r.network.max_order, 1);
  EXPECT_EQ(r.network.stream_counts, (std::vector<int>{62}));
  EXPECT_TRUE(std::isnan(r.network.bifurcation_ratio));
  EXPECT_NEAR(-r.network.flint.slope, 0.0, 1e-6) << "constant slope: no concavity";
  EXPECT_NEAR(r.network.hack.slope, 1.0, 0.05) << "parallel flow: length grows like area";
  const auto json = nlohmann::json::parse(r.json());
  EXPECT_TRUE(json["bifurcation_ratio"].is_null());
  EXPECT_EQ(json["max_strahler_order"], 1);
}

TEST(DrainageMetrics, RecoversTheConcavityOfASyntheticSlopeAreaSurface) {
  // Parallel flow along +x with S = ks A^-0.5 built in: z_i - z_{i+1} = dx ks A_i^-0.5, A_i = i cells.
  const int nx = 256, ny = 16;
  const double dx = 10.0;
  const Domain d = Domain::from_extent({0, 0}, {dx * (nx - 1), dx * (ny - 1)}, {nx, ny});
  std::vector<double> col(nx, 0.0);
  for (int i = nx - 2; i >= 0; --i) col[i] = col[i + 1] + dx * 5.0 * std::pow(std::max(1, i) * dx * dx, -0.5);
  auto in = std::make_shared<Heightfield>(d);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) in->at(i, j) = static_cast<float>(col[i]);
  const auto r = hydrology::drainage_metrics(*in, 100.0);
  EXPECT_NEAR(-r.network.flint.slope, 0.5, 0.05);
  EXPECT_GT(r.network.flint.r2, 0.99);
  // And the fit itself on exact power laws.
  std::vector<double> a, s;
  for (int k = 1; k < 2000; ++k) a.push_back(k * 37.0), s.push_back(3.0 * std::pow(k * 37.0, -0.45));
  const auto fit = hydrology::binned_log_fit(a, s);
  EXPECT_NEAR(fit.slope, -0.45, 1e-9);
  EXPECT_NEAR(fit.r2, 1.0, 1e-12);
}

// ---- WriteCurves --------------------------------------------------------------------------------------------

TEST(WriteCurves, JsonAndObjCarryEveryVertexAndAttribute) {
  Curves cs;
  Curve a;
  a.points = {{0, 0, 10}, {5, 1, 9}, {10, 2, 8.5f}};
  a.width = {1, 1.5f, 2};
  a.attributes["discharge"] = {0.1f, 0.2f, 0.3f};
  a.parent = -1;
  Curve b;
  b.points = {{3, 7, 12}, {5, 1, 9}};
  b.width = {0.5f, 0.75f};
  b.attributes["discharge"] = {0.05f, 0.07f};
  b.parent = 0;
  cs.curves = {a, b};
  const auto dir = std::filesystem::temp_directory_path() / "orogen_write_curves_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  for (const char* name : {"rivers.json", "rivers.obj"}) {
    const Domain d = Domain::from_extent({0, 0}, {10, 10}, {4, 4});
    OutputPolicy policy{dir, false};
    const std::map<std::string, PortValue> inputs{{"in", PortValue(CurvesPtr(std::make_shared<Curves>(cs)))}};
    run_node("WriteCurves", d, {{"path", std::string(name)}}, inputs, policy);
  }
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir)) files.push_back(e.path().filename().string());
  std::sort(files.begin(), files.end());
  EXPECT_EQ(files, (std::vector<std::string>{"rivers.json", "rivers.obj"})) << "no temporary left behind";
  const auto json = nlohmann::json::parse(test::read_text(dir / "rivers.json"));
  ASSERT_EQ(json["type"], "FeatureCollection");
  ASSERT_EQ(json["features"].size(), 2u);
  const auto& f1 = json["features"][1];
  EXPECT_EQ(f1["geometry"]["type"], "LineString");
  EXPECT_EQ(f1["geometry"]["coordinates"][0], (std::vector<double>{3, 7, 12}));
  EXPECT_EQ(f1["properties"]["parent"], 0);
  EXPECT_EQ(f1["properties"]["width"], (std::vector<double>{0.5, 0.75}));
  EXPECT_NEAR(f1["properties"]["discharge"][1].get<double>(), 0.07, 1e-7);
  std::istringstream obj(test::read_text(dir / "rivers.obj"));
  std::vector<std::string> v, l;
  for (std::string line; std::getline(obj, line);) {
    if (line.rfind("v ", 0) == 0) v.push_back(line);
    if (line.rfind("l ", 0) == 0) l.push_back(line);
  }
  EXPECT_EQ(v.size(), 5u);
  EXPECT_EQ(l, (std::vector<std::string>{"l 1 2 3", "l 4 5"}));
  EXPECT_EQ(v[2], "v 10 2 8.5");
  std::filesystem::remove_all(dir);
}

// ---- CLI: reports in --stats --------------------------------------------------------------------------------

TEST(DrainageMetrics, ReportAppearsInCliStats) {
  const auto dir = std::filesystem::temp_directory_path() / "orogen_drainage_stats_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  test::write_text(dir / "g.json", R"({"format": "orogen-graph", "version": 6,
    "domain": {"size": [2000, 2000], "resolution": [96, 96]},
    "nodes": [
      {"id": "h", "type": "FBM", "params": {"feature_size": 700, "amplitude": 100, "seed": 3}},
      {"id": "m", "type": "DrainageMetrics", "inputs": {"in": "h.out"}, "params": {"threshold": 20000}},
      {"id": "w", "type": "WriteHeightfield", "inputs": {"in": "m.out"}, "params": {"path": "order.exr"}}
    ]})");
  const auto r = test::run_process(OROGEN_CLI, {"eval", (dir / "g.json").string(), "-o", (dir / "out").string(),
                                                "--stats", (dir / "stats.json").string(), "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto stats = nlohmann::json::parse(test::read_text(dir / "stats.json"));
  ASSERT_TRUE(stats["reports"].contains("m")) << stats.dump(2);
  const auto& rep = stats["reports"]["m"]["report"];
  EXPECT_EQ(rep["cells"], 96 * 96);
  EXPECT_GE(rep["max_strahler_order"].get<int>(), 1);
  EXPECT_TRUE(rep.contains("concavity_theta"));
  std::filesystem::remove_all(dir);
}

TEST(DrainageMetrics, ReportValuesRoundTripThroughTheCacheFormat) {
  auto rep = std::make_shared<Report>();
  rep->json = R"({"hack_exponent": 0.55, "stream_counts": [12, 3, 1]})";
  const PortValue back = deserialize_value(serialize_value(PortValue(ReportPtr(rep))));
  ASSERT_EQ(port_type_of(back), PortType::Report);
  EXPECT_EQ(std::get<ReportPtr>(back)->json, rep->json);
}

// ---- Node contract -------------------------------------------------------------------------------------------

const char* const kOwnedTypes[] = {"FillDepressions", "Lakes",        "FloodFill", "FlowAccumulation", "FlowDirection",
                                   "Watersheds",      "RiverExtract", "WaterFlow", "DrainageMetrics"};

std::vector<float> first_output(const NodeRun& run) {
  const auto& v = run.outputs.at(0);
  if (const auto* h = std::get_if<HeightfieldPtr>(&v)) return (*h)->data;
  if (const auto* c = std::get_if<CurvesPtr>(&v)) {
    std::vector<float> flat;
    for (const Curve& cv : (*c)->curves) {
      for (const auto& p : cv.points) flat.insert(flat.end(), {p.x, p.y, p.z});
      flat.insert(flat.end(), cv.width.begin(), cv.width.end());
      flat.push_back(static_cast<float>(cv.parent));
    }
    return flat;
  }
  ADD_FAILURE() << "unexpected output type";
  return {};
}

TEST(HydrologyContract, BitIdenticalForOneAndSeveralThreads) {
  const Domain d = Domain::from_extent({0, 0}, {2550, 2550}, {256, 256});
  const auto in = bumpy_field(d);
  const std::map<std::string, std::map<std::string, ParamValue>> params{
      {"FloodFill", {{"position", glm::dvec2(1200, 1300)}}},
      {"RiverExtract", {{"threshold", 4e4}}},
      {"WaterFlow", {{"max_iterations", std::int64_t{50}}}},
      {"DrainageMetrics", {{"threshold", 4e4}}}};
  for (const char* type : kOwnedTypes) {
    SCOPED_TRACE(type);
    const auto it = params.find(type);
    const auto p = it == params.end() ? std::map<std::string, ParamValue>{} : it->second;
    std::vector<std::vector<float>> runs;
    for (int threads : {1, test::several_threads()})
      runs.push_back(test::with_threads(threads, [&] { return first_output(run_node(type, d, p, {{"in", pv(in)}})); }));
    EXPECT_TRUE(test::bit_identical(runs[0], runs[1]));
    if (std::string(type) == "FlowAccumulation")
      for (const char* m : {"d8", "dinf"}) {
        auto pm = p;
        pm["method"] = std::string(m);
        const auto a = test::with_threads(1, [&] { return first_output(run_node(type, d, pm, {{"in", pv(in)}})); });
        const auto b = test::with_threads(test::several_threads(), [&] {
          return first_output(run_node(type, d, pm, {{"in", pv(in)}}));
        });
        EXPECT_TRUE(test::bit_identical(a, b)) << m;
      }
  }
}

TEST(HydrologyContract, AccumulationConvergesWithResolution) {
  // A smooth tilted terrain at 10 m and 5 m: along channels (where the coarse grid resolves them) the
  // contributing area agrees after sampling the fine result at the coarse points (largest value within one
  // coarse cell, as a channel may shift by a fine cell).
  auto smooth = [](double x, double y) {
    return 80.0 * std::sin(x / 300.0) * std::cos(y / 260.0) + 0.08 * x + 0.03 * y;
  };
  const Domain coarse = Domain::from_extent({0, 0}, {2560, 2560}, {257, 257});
  const Domain fine = coarse.resampled({513, 513});
  for (const char* m : {"d8", "mfd"}) {
    const auto a =
        run_node("FlowAccumulation", coarse, {{"method", std::string(m)}}, {{"in", pv(field_from(coarse, smooth))}})
            .get<Heightfield>(0);
    const auto b =
        run_node("FlowAccumulation", fine, {{"method", std::string(m)}}, {{"in", pv(field_from(fine, smooth))}})
            .get<Heightfield>(0);
    std::vector<double> ratio;
    for (int j = 2; j < 255; ++j)
      for (int i = 2; i < 255; ++i) {
        const double ac = a->at(i, j);
        if (ac < 2e5) continue;  // channels of at least 2000 coarse cells
        double af = 0.0;
        for (int dj = -2; dj <= 2; ++dj)
          for (int di = -2; di <= 2; ++di) af = std::max<double>(af, b->at(2 * i + di, 2 * j + dj));
        ratio.push_back(af / ac);
      }
    ASSERT_GT(ratio.size(), 50u) << m;
    std::sort(ratio.begin(), ratio.end());
    const double median = ratio[ratio.size() / 2];
    EXPECT_NEAR(median, 1.0, 0.1) << m;
  }
}

TEST(HydrologyContract, EveryParameterAndInputChangesTheCacheKey) {
  const Domain d = Domain::from_extent({0, 0}, {1024, 1024}, {64, 64});
  for (const char* type : kOwnedTypes) {
    SCOPED_TRACE(type);
    expect_every_param_changes_key(type, d);
    expect_every_input_changes_key(type, d);
  }
  expect_every_param_changes_key("WriteCurves", d);
  expect_every_input_changes_key("WriteCurves", d);
}

TEST(HydrologyContract, DeclarationsAreDocumented) {
  std::vector<std::string> types(std::begin(kOwnedTypes), std::end(kOwnedTypes));
  types.push_back("WriteCurves");
  for (const auto& type : types) {
    const NodeType* t = NodeRegistry::instance().find(type);
    ASSERT_NE(t, nullptr) << type;
    EXPECT_FALSE(t->description.empty()) << type;
    for (const auto& p : t->inputs) EXPECT_FALSE(p.description.empty()) << type << "." << p.name;
    for (const auto& p : t->outputs) EXPECT_FALSE(p.description.empty()) << type << "." << p.name;
    for (const auto& p : t->params) EXPECT_FALSE(p.description.empty()) << type << "." << p.name;
  }
}

}  // namespace
}  // namespace orogen
