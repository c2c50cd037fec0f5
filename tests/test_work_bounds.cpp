// Work bounds (issue #30, 9-11): step and sub-step counts from checked arithmetic, a declared ceiling on a
// node's work refused up front with the parameters to change, non-finite inputs to simulations refused with
// the node and port named, and no invariant surfacing as std::logic_error on legal parameters.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "evaluator/run_node.h"
#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/points.h"
#include "nodes/hydrology/rivers.h"
#include "support/test_paths.h"
#include "nodes/common/work_bounds.h"
#include "nodes/common/work_poll.h"

namespace orogen {
namespace {

HeightfieldPtr fbm_like(const Domain& d, double amplitude) {
  auto h = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i)
      h->at(i, j) = static_cast<float>(amplitude * (0.5 + 0.25 * std::sin(0.9 * i) + 0.25 * std::cos(0.7 * j)));
  return h;
}

// The sum of the cluster member counts in a KMeansClusters report.
long member_count(const std::string& json) {
  long total = 0;
  const auto j = nlohmann::json::parse(json);
  for (const auto& c : j.at("clusters")) total += c.at("count").get<long>();
  return total;
}

// The node's NodeError message, or "" if it succeeded (a logic_error or any other exception fails the test).
std::string node_error(const std::string& type, const Domain& d, const std::map<std::string, ParamValue>& params,
                       const std::map<std::string, PortValue>& inputs = {}) {
  try {
    (void)run_node(type, d, params, inputs);
  } catch (const NodeError& e) {
    return e.what();
  }
  return "";
}

TEST(CheckedCount, CountsFitOrAreRefusedWithTheParametersToChange) {
  EXPECT_EQ(checked_count(2.5, "steps", "raise x"), 3);
  EXPECT_EQ(checked_count(-4.0, "steps", "raise x"), 1);
  EXPECT_EQ(checked_count(0.0, "steps", "raise x", 10, true), 0);
  EXPECT_EQ(checked_count(2147483647.0, "steps", "raise x"), 2147483647);
  for (const double bad :
       {2147483648.0, 1e10, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN()}) {
    try {
      (void)checked_count(bad, "time steps (duration / time_step)", "raise time_step or lower duration");
      ADD_FAILURE() << bad << " was accepted";
    } catch (const NodeError& e) {
      EXPECT_NE(std::string(e.what()).find("raise time_step or lower duration"), std::string::npos) << e.what();
    }
  }
  EXPECT_NO_THROW(check_work(kMaxNodeWork, "updates", "less"));
  EXPECT_THROW(check_work(kMaxNodeWork * 2, "updates", "less"), NodeError);
  EXPECT_THROW(check_work(std::numeric_limits<double>::quiet_NaN(), "updates", "less"), NodeError);
}

TEST(WorkPoll, WithoutAContextNothingIsChecked) {
  // Without a context nothing is checked.
  WorkPoll none(nullptr, 2);
  for (int k = 0; k < 10; ++k) none();
  SUCCEED();
}

// 9: duration 1e10 yr in 1-yr steps ran as one 1e10-yr step (int overflow) and exited 0.
TEST(WorkBounds, StreamPowerStepCountOverflowIsRefused) {
  const Domain d = Domain::from_extent({0, 0}, {640, 640}, {33, 33});
  const std::string e =
      node_error("StreamPower", d, {{"duration", 1e10}, {"time_step", 1.0}}, {{"in", PortValue(fbm_like(d, 300.0))}});
  EXPECT_NE(e.find("time_step"), std::string::npos) << e;
  EXPECT_NE(e.find("duration"), std::string::npos) << e;
}

// PoissonDisk with radii 1e6 times apart built a neighbor-offset table of 1e15 cells before placing any point,
// out of reach of the cancel (found by fuzz_graph_eval): refused up front naming the radii.
TEST(WorkBounds, PoissonDiskRadiiFarApartAreRefused) {
  const Domain d = Domain::from_extent({0, 0}, {1, 1}, {2, 2});
  const std::string e =
      node_error("PoissonDisk", d, {{"class_count", std::int64_t{2}}, {"radius_0", 9999.99}, {"radius_1", 0.01}}, {});
  EXPECT_NE(e.find("radius_0"), std::string::npos) << e;
  EXPECT_NE(e.find("radius_1"), std::string::npos) << e;
  EXPECT_EQ(node_error("PoissonDisk", d, {{"class_count", std::int64_t{2}}, {"radius_0", 2.0}, {"radius_1", 0.5}}, {}),
            "");
}

// ThermalErosion's iteration count (2 x travel_distance / spacing) did not fit an int at a long travel on a
// fine grid (UBSan's float-cast-overflow): refused up front with the parameters to change.
TEST(WorkBounds, ThermalErosionIterationCountIsCheckedNotCast) {
  const Domain d = Domain::from_extent({0, 0}, {1e-4, 1e-4}, {17, 17});
  const std::string e =
      node_error("ThermalErosion", d, {{"travel_distance", 1e5}}, {{"in", PortValue(fbm_like(d, 1e-3))}});
  EXPECT_NE(e.find("travel_distance"), std::string::npos) << e;
  const Domain coarse = Domain::from_extent({0, 0}, {160, 160}, {17, 17});
  EXPECT_EQ(
      node_error("ThermalErosion", coarse, {{"travel_distance", 50.0}}, {{"in", PortValue(fbm_like(coarse, 30.0))}}),
      "");
}

// A river segment of infinite width (a width law's overflow) or with a non-finite end is drawn without
// casting an infinite bound to int: infinitely wide covers the grid, non-finite ends cover nothing.
TEST(WorkBounds, RiverMaskOfInfiniteAndNonFiniteSegments) {
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {11, 11});
  Curves wide;
  Curve c;
  c.points = {{50, 50, 0}, {60, 50, 0}};
  c.width = {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity()};
  wide.curves.push_back(c);
  Heightfield mask(d);
  hydrology::draw_curves(wide, mask);
  for (float v : mask.data) EXPECT_EQ(v, 1.0f);
  Curves broken;
  c.points = {{50, 50, 0}, {std::numeric_limits<float>::quiet_NaN(), 50, 0}};
  c.width = {5.0f, 5.0f};
  broken.curves.push_back(c);
  Heightfield none(d);
  hydrology::draw_curves(broken, none);
  for (float v : none.data) EXPECT_EQ(v, 0.0f);
}

// 9: diffusion 100 on a 0.25 m grid took one explicit sub-step instead of ~7e11 (a 300 m relief came out
// 138,912 m high).
// Droplets x steps x brush taps beyond the ceiling (1e8 droplets per km^2 of a 10 km map, 1e7 steps each) is
// refused before the first droplet, naming the parameters; a huge domain's droplet count is checked, not cast.
TEST(WorkBounds, HydraulicErosionPlansAreCheckedAgainstTheCeiling) {
  const Domain d = Domain::from_extent({0, 0}, {10000, 10000}, {33, 33});
  const std::string e =
      node_error("HydraulicErosion", d, {{"droplets_per_km2", 1e8}, {"lifetime", 1e5}, {"step_length", 0.01}},
                 {{"in", PortValue(fbm_like(d, 300.0))}});
  EXPECT_NE(e.find("per-node ceiling"), std::string::npos) << e;
  EXPECT_NE(e.find("droplets_per_km2"), std::string::npos) << e;
  EXPECT_NE(e.find("step_length"), std::string::npos) << e;
  const Domain huge = Domain::from_extent({0, 0}, {1e11, 1e11}, {9, 9});
  const std::string h =
      node_error("HydraulicErosion", huge, {{"droplets_per_km2", 1e8}}, {{"in", PortValue(fbm_like(huge, 300.0))}});
  EXPECT_NE(h.find("droplets_per_km2"), std::string::npos) << h;
}

// WaterFlow's max_iterations x samples beyond the ceiling is refused up front.
TEST(WorkBounds, WaterFlowIterationsAreCheckedAgainstTheCeiling) {
  const Domain d = Domain::from_extent({0, 0}, {100000, 100000}, {3300, 3300});
  const Domain small = Domain::from_extent({0, 0}, {100, 100}, {9, 9});
  // The check comes before anything of the grid's size is allocated, so a flat field is enough.
  const auto flat = std::make_shared<Heightfield>(d, 1.0f);
  const std::string e =
      node_error("WaterFlow", d, {{"max_iterations", std::int64_t{1000000}}}, {{"in", PortValue(flat)}});
  EXPECT_NE(e.find("max_iterations"), std::string::npos) << e;
  EXPECT_NO_THROW(run_node("WaterFlow", small, {{"max_iterations", std::int64_t{1000000}}},
                           {{"in", PortValue(fbm_like(small, 10.0))}}));
}

TEST(WorkBounds, StreamPowerDiffusionSubStepsAreCountedOrRefused) {
  const Domain d = Domain::from_extent({0, 0}, {16, 16}, {65, 65});
  for (const double time_step : {1e4, 1e8}) {
    const std::string e =
        node_error("StreamPower", d, {{"diffusion", 100.0}, {"time_step", time_step}, {"duration", 1e10}},
                   {{"in", PortValue(fbm_like(d, 300.0))}});
    EXPECT_NE(e.find("diffusion"), std::string::npos) << e;
  }
  // A plan within the ceiling still runs, and diffusion never raises the relief.
  const auto run = run_node(
      "StreamPower", d, {{"diffusion", 100.0}, {"time_step", 1.0}, {"duration", 2.0}, {"uplift_rate", 0.0}, {"k", 0.0}},
      {{"in", PortValue(fbm_like(d, 300.0))}});
  const auto out = run.get<Heightfield>(0);
  for (float v : out->data) {
    EXPECT_TRUE(std::isfinite(v));
    EXPECT_LE(v, 300.0f + 1e-3f);
    EXPECT_GE(v, -1e-3f);
  }
}

// 10: +inf rainfall on a few samples made the CFL step 0: simulated time never advanced.
TEST(WorkBounds, PipeErosionRefusesNonFiniteRainfallNamingThePort) {
  const Domain d = Domain::from_extent({0, 0}, {320, 320}, {33, 33});
  auto rain = std::make_shared<Heightfield>(d);
  for (auto& v : rain->data) v = 50.0f;
  rain->at(3, 4) = std::numeric_limits<float>::infinity();
  const std::string e = node_error(
      "PipeErosion", d, {}, {{"in", PortValue(fbm_like(d, 50.0))}, {"rainfall_rate", PortValue(HeightfieldPtr(rain))}});
  EXPECT_NE(e.find("PipeErosion"), std::string::npos) << e;
  EXPECT_NE(e.find("'rainfall_rate'"), std::string::npos) << e;  // the node's port, not the library's name
  EXPECT_NE(e.find("(3, 4)"), std::string::npos) << e;
}

// Non-finite terrain heights: every simulation refuses them up front, naming itself, the port `in`, the kind
// of value and the first bad sample (before, a NaN height spread through the gradients or ran silently).
TEST(NonFiniteHeights, EverySimulationRefusesNaNAndInfiniteHeightsNamingThePort) {
  const Domain d = Domain::from_extent({0, 0}, {320, 320}, {33, 33});
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (const char* type : {"HydraulicErosion", "StreamPower", "ThermalErosion", "PipeErosion", "WaterFlow"})
    for (const float bad : {nan, inf}) {
      auto h = std::make_shared<Heightfield>(*fbm_like(d, 50.0));
      h->at(5, 7) = bad;
      h->at(20, 9) = bad;  // only the first one in row order is named
      const std::string e = node_error(type, d, {}, {{"in", PortValue(HeightfieldPtr(h))}});
      EXPECT_NE(e.find(type), std::string::npos) << type << ": " << e;
      EXPECT_NE(e.find("input 'in'"), std::string::npos) << type << ": " << e;
      EXPECT_NE(e.find(std::isnan(bad) ? "NaN" : "infinite"), std::string::npos) << type << ": " << e;
      EXPECT_NE(e.find("(5, 7)"), std::string::npos) << type << ": " << e;
    }
}

// The same check covers each simulation's other fields, under the node's port names.
TEST(NonFiniteHeights, DrivingFieldsAreRefusedUnderTheirPortNames) {
  const Domain d = Domain::from_extent({0, 0}, {320, 320}, {33, 33});
  const std::pair<const char*, const char*> cases[] = {
      {"StreamPower", "uplift"}, {"ThermalErosion", "hardness"}, {"WaterFlow", "rainfall"},
      {"WaterFlow", "sinks"},    {"HydraulicErosion", "mask"},   {"PipeErosion", "evaporation_factor"}};
  for (const auto& [type, port] : cases) {
    auto field = std::make_shared<Heightfield>(d);
    for (auto& v : field->data) v = 0.5f;
    field->at(2, 3) = -std::numeric_limits<float>::infinity();
    const std::string e =
        node_error(type, d, {}, {{"in", PortValue(fbm_like(d, 50.0))}, {port, PortValue(HeightfieldPtr(field))}});
    EXPECT_NE(e.find("input '" + std::string(port) + "'"), std::string::npos) << type << ": " << e;
    EXPECT_NE(e.find("(2, 3)"), std::string::npos) << type << ": " << e;
  }
}

// 10 (the rule behind it): whatever makes the water depth overflow, the time step never becomes 0 silently.
TEST(WorkBounds, PipeErosionOverflowingWaterIsAnErrorNotAZeroTimeStep) {
  const Domain d = Domain::from_extent({0, 0}, {320, 320}, {33, 33});
  auto rain = std::make_shared<Heightfield>(d);
  for (auto& v : rain->data) v = 3e38f;
  const std::string e =
      node_error("PipeErosion", d, {{"duration", 1e4}},
                 {{"in", PortValue(fbm_like(d, 50.0))}, {"rainfall_rate", PortValue(HeightfieldPtr(rain))}});
  EXPECT_NE(e.find("PipeErosion"), std::string::npos) << e;
}

// 11: size [10, 1e7] failed an internal invariant (std::logic_error "a cell stayed open with every site
// mirrored": circumcentres of nearly flat triangles rounded outside the map). Every aspect ratio in range gives
// an island, else a clear NodeError naming `size`.
TEST(WorkBounds, VoronoiIslandAtExtremeAspectRatiosIsAResultOrAClearError) {
  const Domain d = Domain::from_extent({0, 0}, {320, 320}, {33, 33});
  int islands = 0;
  for (const glm::dvec2 size : {glm::dvec2(10.0, 1e7), glm::dvec2(1e7, 10.0), glm::dvec2(1.0, 1e7),
                                glm::dvec2(1e7, 1.0), glm::dvec2(100.0, 1e7)})
    for (const std::string distribution : {"poisson", "uniform"})
      for (const std::int64_t relaxation : {std::int64_t{2}, std::int64_t{3}}) {
        try {
          const auto run = run_node("VoronoiIsland", d,
                                    {{"size", size}, {"distribution", distribution}, {"relaxation", relaxation}});
          EXPECT_FALSE(run.get<PolygonMap>(0)->cells.empty());
          ++islands;
        } catch (const NodeError& e) {
          EXPECT_NE(std::string(e.what()).find("size"), std::string::npos) << e.what();
        }
      }
  EXPECT_EQ(islands, 20) << "every one of these aspect ratios is resolved today";
}

// ShadePlacement's step count was an int cast of up to 2e10 (undefined; nothing shaded): tiny crowns far
// below their casters run in 64 bits, clipped to the casters' extent (the sanitizer build checks the casts).
TEST(WorkBounds, ShadePlacementWithTinyCrownsFarAboveRuns) {
  const Domain d = Domain::from_extent({0, 0}, {320, 320}, {33, 33});
  auto casters = std::make_shared<Points>();
  auto candidates = std::make_shared<Points>();
  for (int k = 0; k < 100; ++k) {
    const std::size_t c = casters->add({static_cast<float>(k % 10) * 0.05f, static_cast<float>(k / 10) * 0.05f, 1e6f});
    casters->scale[c] = glm::vec3(0.01f);
    candidates->add({static_cast<float>(k % 10) * 30.0f, static_cast<float>(k / 10) * 30.0f, 0.0f});
  }
  const auto run = run_node("ShadePlacement", d,
                            {{"crown_radius", 0.01}, {"sun_elevation", 1.0}, {"preference", std::string("any")}},
                            {{"in", PortValue(std::shared_ptr<const Points>(candidates))},
                             {"casters", PortValue(std::shared_ptr<const Points>(casters))}});
  EXPECT_EQ(run.get<Points>(0)->size(), 100u);
}

// 19: KMeansClusters gave NaN cells a real cluster label. Such a cell belongs to no cluster: NaN id,
// transparent colour, and it counts in no cluster.
TEST(NonFiniteRule, KMeansCellsWithNaNFeaturesGetNoCluster) {
  const Domain d = Domain::from_extent({0, 0}, {30, 30}, {4, 4});
  auto img = std::make_shared<Image>(d, 2);
  img->channel_names = {"slope", "temperature_jan"};
  for (std::size_t q = 0; q < 16; ++q) {
    img->data[2 * q] = static_cast<float>(q % 4);
    img->data[2 * q + 1] = static_cast<float>(q / 4);
  }
  img->data[2 * 5 + 1] = std::numeric_limits<float>::quiet_NaN();
  img->data[2 * 9] = std::numeric_limits<float>::infinity();
  const auto run = run_node("KMeansClusters", d, {{"k", std::int64_t{3}}}, {{"in", PortValue(ImagePtr(img))}});
  const auto ids = run.get<Heightfield>(0);
  const auto color = run.get<Image>(2);
  for (std::size_t q = 0; q < 16; ++q) {
    if (q == 5 || q == 9) {
      EXPECT_TRUE(std::isnan(ids->data[q])) << q;
      EXPECT_EQ(color->data[4 * q + 3], 0.0f) << q;
    } else {
      EXPECT_GE(ids->data[q], 0.0f) << q;
      EXPECT_LT(ids->data[q], 3.0f) << q;
    }
  }
  EXPECT_EQ(member_count(run.get<Report>(1)->json), 14);
}

// 19: a grid mesh with NaN heights was written as "v 21 32 nan" (OBJ) and NaN positions (GLB, STL), exit 0.
TEST(NonFiniteRule, MeshesWithNonFinitePositionsAreRefusedInEveryFormat) {
  const Domain d = Domain::from_extent({0, 0}, {30, 30}, {8, 8});
  auto h = std::make_shared<Heightfield>(*fbm_like(d, 10.0));
  h->at(3, 2) = std::numeric_limits<float>::quiet_NaN();
  const auto mesh = run_node("HeightfieldToMesh", d, {}, {{"in", PortValue(HeightfieldPtr(h))}});
  OutputPolicy policy;
  policy.output_dir = test::scratch_dir("work-bounds-nan-mesh");
  for (const std::string name : {"m.obj", "m.glb", "m.stl", "m.ply"}) {
    try {
      (void)run_node("WriteMesh", d, {{"path", name}}, {{"in", mesh.outputs.at(0)}}, policy);
      ADD_FAILURE() << name << " was written";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("non-finite"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(policy.output_dir / name)) << name;
  }
}

}  // namespace
}  // namespace orogen
