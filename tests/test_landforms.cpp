// Landform primitives (nodes/landform): analytic heights of each shape, world-space consistency (a sub-domain
// equals the same samples of the full domain bit for bit), determinism for a seed, and refused parameters.
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "field_ops_fixtures.h"
#include "graph/exec_context.h"
#include "graph/table_value.h"
#include "nodes/landform/canyon.h"
#include "nodes/landform/crater.h"
#include "nodes/landform/dunes.h"
#include "nodes/landform/mountain.h"
#include "nodes/landform/plateau.h"
#include "nodes/landform/ridge.h"
#include "nodes/landform/volcano.h"

namespace orogen {
namespace {

using test::bit_identical;
using test::run_field;

constexpr double kDeg = std::numbers::pi / 180.0;

// 0..1000 m at 5 m: (500, 500) is sample (100, 100).
Domain square() { return Domain::from_extent({0, 0}, {1000, 1000}, {201, 201}); }

// The message of the NodeError `fn` throws (empty if none).
template <class Fn>
std::string error_of(Fn&& fn) {
  try {
    fn();
  } catch (const NodeError& e) {
    return e.what();
  }
  return {};
}

// ---- Volcano ----

TEST(Volcano, RimAtHeightCraterFloorBelowConcaveFlanksZeroBeyond) {
  const Domain d = square();
  const auto h = run_field("Volcano", d,
                           {{"position", glm::dvec2(500, 500)},
                            {"radius", 400.0},
                            {"height", 300.0},
                            {"flank_exponent", 1.6},
                            {"crater_radius", 50.0},
                            {"crater_depth", 60.0}});
  EXPECT_FLOAT_EQ(h->at(100, 100), 240.0f);  // floor: 60 m below the rim
  EXPECT_FLOAT_EQ(h->at(110, 100), 300.0f);  // rim, r = 50 m
  EXPECT_FLOAT_EQ(h->at(100, 110), 300.0f);
  EXPECT_NEAR(h->at(105, 100), 300.0 - 60.0 * (1.0 - 0.25), 1e-4);           // r = 25 m in the bowl
  EXPECT_NEAR(h->at(140, 100), 300.0 * std::pow(200.0 / 350.0, 1.6), 1e-3);  // r = 200 m on the flank
  EXPECT_EQ(h->at(180, 100), 0.0f);                                          // r = 400 m: the foot
  EXPECT_EQ(h->at(0, 0), 0.0f);
  float highest = -1e9f;
  for (float v : h->data) highest = std::max(highest, v);
  EXPECT_FLOAT_EQ(highest, 300.0f);  // nothing above the rim
  // Concave flanks: the slope decreases from the rim toward the foot.
  for (int i = 112; i < 178; ++i) EXPECT_GT(h->at(i, 100) - h->at(i + 1, 100), h->at(i + 1, 100) - h->at(i + 2, 100));
}

TEST(Volcano, RefusesACraterWiderThanTheBase) {
  const std::string e = error_of([] { run_field("Volcano", square(), {{"radius", 300.0}, {"crater_radius", 300.0}}); });
  EXPECT_NE(e.find("Volcano"), std::string::npos) << e;
  EXPECT_NE(e.find("crater_radius"), std::string::npos) << e;
}

// ---- Crater ----

TEST(Crater, FloorDepthRimHeightAndEjectaFalloff) {
  const Domain d = Domain::from_extent({0, 0}, {4000, 4000}, {801, 801});  // 5 m; center (2000, 2000) = (400, 400)
  const auto h = run_field("Crater", d,
                           {{"position", glm::dvec2(2000, 2000)},
                            {"radius", 200.0},
                            {"depth", 80.0},
                            {"rim_height", 16.0},
                            {"base_height", 10.0}});
  EXPECT_FLOAT_EQ(h->at(400, 400), -70.0f);                 // 80 m below the surface at 10 m
  EXPECT_FLOAT_EQ(h->at(440, 400), 26.0f);                  // rim crest at r = 200 m
  EXPECT_NEAR(h->at(420, 400), -70.0 + 96.0 * 0.25, 1e-4);  // r = 100 m: a quarter of the way up
  EXPECT_NEAR(h->at(480, 400), 10.0 + 16.0 / 8.0, 1e-4);    // r = 400 m: ejecta (r / R)^-3
  EXPECT_NEAR(h->at(400, 0), 10.0 + 16.0 / 1000.0, 1e-4);   // r = 2000 m: nearly the base
  // The bowl rises monotonically to the rim, the ejecta fall monotonically beyond it.
  for (int i = 400; i < 440; ++i) EXPECT_LT(h->at(i, 400), h->at(i + 1, 400));
  for (int i = 440; i < 800; ++i) EXPECT_GT(h->at(i, 400), h->at(i + 1, 400));
  // A flat floor within floor_radius.
  const auto flat =
      run_field("Crater", d, {{"position", glm::dvec2(2000, 2000)}, {"radius", 200.0}, {"floor_radius", 100.0}});
  for (int i = 400; i <= 420; ++i) EXPECT_FLOAT_EQ(flat->at(i, 400), -80.0f);
  EXPECT_GT(flat->at(421, 400), -80.0f);
}

TEST(Crater, RefusesAFloorWiderThanTheRim) {
  const std::string e = error_of([] { run_field("Crater", square(), {{"radius", 100.0}, {"floor_radius", 150.0}}); });
  EXPECT_NE(e.find("floor_radius"), std::string::npos) << e;
}

// ---- Plateau ----

TEST(Plateau, FlatTopEscarpmentAndBaseFarAway) {
  const Domain d = square();
  const auto h = run_field("Plateau", d,
                           {{"position", glm::dvec2(500, 500)},
                            {"radius", 200.0},
                            {"height", 120.0},
                            {"escarpment_width", 100.0},
                            {"base_height", 5.0},
                            {"edge_roughness", 0.0}});
  for (int j = 0; j < 201; ++j)
    for (int i = 0; i < 201; ++i) {
      const double r = std::hypot(d.x(i) - 500, d.y(j) - 500);
      if (r <= 200.0) ASSERT_EQ(h->at(i, j), 125.0f) << i << "," << j;
      if (r >= 300.0) ASSERT_EQ(h->at(i, j), 5.0f) << i << "," << j;
    }
  EXPECT_NEAR(h->at(150, 100), 5.0 + 120.0 * 0.25, 1e-4);  // halfway down the escarpment: (1 - 0.5)^2
}

TEST(Plateau, RaggedOutlineKeepsTheTopFlatAndIsSeeded) {
  const Domain d = square();
  const std::map<std::string, ParamValue> p{
      {"position", glm::dvec2(500, 500)}, {"radius", 250.0},        {"height", 100.0},
      {"escarpment_width", 60.0},         {"edge_roughness", 50.0}, {"seed", std::uint64_t{7}}};
  const auto h = run_field("Plateau", d, p);
  int top_outside_circle = 0, base_inside_circle = 0;
  for (int j = 0; j < 201; ++j)
    for (int i = 0; i < 201; ++i) {
      const double r = std::hypot(d.x(i) - 500, d.y(j) - 500);
      if (r <= 200.0) ASSERT_EQ(h->at(i, j), 100.0f) << i << "," << j;  // inside radius - roughness
      if (r >= 360.0) ASSERT_EQ(h->at(i, j), 0.0f) << i << "," << j;    // beyond radius + width + roughness
      if (r > 252.0 && h->at(i, j) == 100.0f) ++top_outside_circle;
      if (r < 248.0 && h->at(i, j) < 100.0f) ++base_inside_circle;
    }
  EXPECT_GT(top_outside_circle, 0);  // the outline wanders out ...
  EXPECT_GT(base_inside_circle, 0);  // ... and in
  EXPECT_TRUE(bit_identical(run_field("Plateau", d, p)->data, h->data));
  auto other = p;
  other["seed"] = std::uint64_t{8};
  EXPECT_FALSE(bit_identical(run_field("Plateau", d, other)->data, h->data));
}

// ---- Ridge ----

TEST(Ridge, CrestOnTheSegmentProfileAcrossAndTaperedEnds) {
  const Domain d = square();
  const std::map<std::string, ParamValue> p{{"start", glm::dvec2(200, 500)},
                                            {"end", glm::dvec2(800, 500)},
                                            {"height", 200.0},
                                            {"half_width", 100.0},
                                            {"sharpness", 0.6},
                                            {"taper_length", 100.0},
                                            {"meander", 0.0},
                                            {"roughness", 0.0}};
  const auto h = run_field("Ridge", d, p);
  for (int i = 80; i <= 120; ++i) EXPECT_FLOAT_EQ(h->at(i, 100), 200.0f) << i;  // crest, away from the ends
  // u = 0.5: 0.4 x bell 0.5 + 0.6 x (1 - 0.5)^2 = 0.35.
  EXPECT_NEAR(h->at(100, 110), 70.0, 1e-4);
  EXPECT_NEAR(h->at(100, 90), 70.0, 1e-4);
  EXPECT_EQ(h->at(100, 120), 0.0f);  // at half_width: the foot
  EXPECT_EQ(h->at(100, 150), 0.0f);
  EXPECT_EQ(h->at(160, 100), 0.0f);          // the end itself
  EXPECT_NEAR(h->at(50, 100), 100.0, 1e-4);  // 50 m from the end: smoothstep(0.5) = 0.5
  EXPECT_EQ(h->at(30, 100), 0.0f);           // beyond the end
  // Rounded (sharpness 0) against knife-edge (1) at u = 0.5.
  auto round = p, knife = p;
  round["sharpness"] = 0.0;
  knife["sharpness"] = 1.0;
  EXPECT_NEAR(run_field("Ridge", d, round)->at(100, 110), 100.0, 1e-4);
  EXPECT_NEAR(run_field("Ridge", d, knife)->at(100, 110), 50.0, 1e-4);
  // Without a taper the crest keeps its height to the ends.
  auto blunt = p;
  blunt["taper_length"] = 0.0;
  EXPECT_FLOAT_EQ(run_field("Ridge", d, blunt)->at(160, 100), 200.0f);
}

TEST(Ridge, BendsAndRoughnessStayUnderTheEnvelopeAndAreSeeded) {
  const Domain d = square();
  std::map<std::string, ParamValue> p{{"start", glm::dvec2(200, 500)},
                                      {"end", glm::dvec2(800, 500)},
                                      {"height", 200.0},
                                      {"half_width", 100.0},
                                      {"taper_length", 0.0},
                                      {"meander", 0.0},
                                      {"roughness", 80.0},
                                      {"seed", std::uint64_t{4}}};
  const auto rough = run_field("Ridge", d, p);
  auto smooth_p = p;
  smooth_p["roughness"] = 0.0;
  const auto smooth = run_field("Ridge", d, smooth_p);
  double deviation = 0.0;
  for (std::size_t k = 0; k < smooth->data.size(); ++k) {
    const double e = smooth->data[k] / 200.0;
    ASSERT_LE(std::abs(rough->data[k] - smooth->data[k]), 40.0 * e + 1e-3) << k;  // roughness / 2 x envelope
    deviation = std::max(deviation, static_cast<double>(std::abs(rough->data[k] - smooth->data[k])));
  }
  EXPECT_GT(deviation, 10.0);
  // Meanders move the crest off the axis, by no more than meander x sqrt(2).
  p["roughness"] = 0.0;
  p["meander"] = 50.0;
  const auto bent = run_field("Ridge", d, p);
  int crest_off_axis = 0;
  for (int j = 0; j < 201; ++j)
    for (int i = 0; i < 201; ++i) {
      const double off = std::abs(d.y(j) - 500);
      if (off > 100.0 + 50.0 * std::sqrt(2.0)) ASSERT_EQ(bent->at(i, j), 0.0f) << i << "," << j;
    }
  for (int i = 50; i <= 150; ++i) {  // the highest sample of each column, away from the ends
    int top = 0;
    for (int j = 1; j < 201; ++j)
      if (bent->at(i, j) > bent->at(i, top)) top = j;
    if (std::abs(d.y(top) - 500) > 7.0) ++crest_off_axis;  // more than a sample off
  }
  EXPECT_GT(crest_off_axis, 0);
  EXPECT_TRUE(bit_identical(run_field("Ridge", d, p)->data, bent->data));
  p["seed"] = std::uint64_t{5};
  EXPECT_FALSE(bit_identical(run_field("Ridge", d, p)->data, bent->data));
}

TEST(Ridge, RefusesASegmentOfNoLength) {
  const std::string e = error_of([] {
    run_field("Ridge", square(), {{"start", glm::dvec2(300, 300)}, {"end", glm::dvec2(300, 300)}});
  });
  EXPECT_NE(e.find("Ridge"), std::string::npos) << e;
  EXPECT_NE(e.find("start and end"), std::string::npos) << e;
}

// ---- Canyon ----

// A Canyon path table from points.
TableValue path(const std::vector<glm::dvec2>& points) {
  TableValue t{{"x", "y"}, {}};
  for (const auto& q : points) t.rows.push_back({q.x, q.y});
  return t;
}

TEST(Canyon, DepthOnThePathWallsAtTheirSlopeZeroFarAway) {
  const Domain d = square();
  std::map<std::string, ParamValue> p{{"path", path({{0, 500}, {1000, 500}})},
                                      {"depth", 100.0},
                                      {"floor_width", 40.0},
                                      {"wall_slope", 45.0},
                                      {"taper_length", 0.0},
                                      {"meander", 0.0}};
  const auto h = run_field("Canyon", d, p);
  for (int i = 0; i <= 200; ++i) {
    ASSERT_FLOAT_EQ(h->at(i, 100), -100.0f) << i;  // on the path
    ASSERT_FLOAT_EQ(h->at(i, 104), -100.0f) << i;  // floor edge, 20 m off
    ASSERT_NEAR(h->at(i, 114), -50.0, 1e-4) << i;  // 50 m up a 100 m wide wall at 45 degrees
    ASSERT_NEAR(h->at(i, 124), 0.0f, 1e-9) << i;   // the rim, 120 m off
    ASSERT_EQ(h->at(i, 180), 0.0f) << i;
  }
  // The wall's slope is wall_slope.
  EXPECT_NEAR(std::atan((h->at(100, 115) - h->at(100, 113)) / 10.0) / kDeg, 45.0, 1e-3);
  // Terraces: flat benches and risers at twice the gradient, the same depth and width.
  p["terraces"] = std::int64_t{2};
  const auto t = run_field("Canyon", d, p);
  EXPECT_FLOAT_EQ(t->at(100, 109), -100.0f);  // first bench, a quarter up the wall
  EXPECT_NEAR(t->at(100, 119), -50.0, 1e-4);  // second bench
  EXPECT_NEAR(t->at(100, 116), -50.0, 1e-4);  // f = 0.6: still on the second bench
  EXPECT_NEAR(t->at(100, 112), -70.0, 1e-4);  // f = 0.4: 60% up the first riser, 0.3 of the depth
  EXPECT_NEAR(t->at(100, 122), -20.0, 1e-4);  // f = 0.9: 60% up the second riser
  EXPECT_NEAR(t->at(100, 124), 0.0f, 1e-9);
  EXPECT_EQ(t->at(100, 130), 0.0f);
}

TEST(Canyon, MeandersStayWithinTheirAmplitudeAndAreSeeded) {
  const Domain d = square();
  std::map<std::string, ParamValue> p{{"path", path({{0, 500}, {1000, 500}})},
                                      {"depth", 80.0},
                                      {"floor_width", 20.0},
                                      {"wall_slope", 60.0},
                                      {"taper_length", 0.0},
                                      {"meander", 60.0},
                                      {"seed", std::uint64_t{3}}};
  const auto h = run_field("Canyon", d, p);
  const double reach = 60.0 * std::sqrt(2.0) + 10.0 + 80.0 / std::tan(60.0 * kDeg);
  int floor_off_axis = 0;
  for (int j = 0; j < 201; ++j)
    for (int i = 0; i < 201; ++i) {
      const double off = std::abs(d.y(j) - 500);
      ASSERT_LE(h->at(i, j), 0.0f);
      ASSERT_GE(h->at(i, j), -80.0f);
      if (off > reach) ASSERT_EQ(h->at(i, j), 0.0f) << i << "," << j;
      if (off > 20.0 && h->at(i, j) == -80.0f) ++floor_off_axis;
    }
  EXPECT_GT(floor_off_axis, 0);  // the path really bends
  EXPECT_TRUE(bit_identical(run_field("Canyon", d, p)->data, h->data));
  p["seed"] = std::uint64_t{4};
  EXPECT_FALSE(bit_identical(run_field("Canyon", d, p)->data, h->data));
}

TEST(Canyon, FollowsABentPathAndTapersByTheDistanceAlongIt) {
  const Domain d = square();
  // An L: 300 m east, then 600 m north; 900 m long.
  const auto h = run_field("Canyon", d,
                           {{"path", path({{200, 200}, {500, 200}, {500, 800}})},
                            {"depth", 60.0},
                            {"floor_width", 20.0},
                            {"wall_slope", 45.0},
                            {"taper_length", 100.0},
                            {"meander", 0.0}});
  EXPECT_FLOAT_EQ(h->at(70, 40), -60.0f);     // (350, 200) on the first leg
  EXPECT_FLOAT_EQ(h->at(100, 40), -60.0f);    // the corner
  EXPECT_FLOAT_EQ(h->at(100, 100), -60.0f);   // (500, 500) on the second leg
  EXPECT_NEAR(h->at(50, 40), -30.0, 1e-4);    // 50 m from the start: smoothstep(0.5)
  EXPECT_NEAR(h->at(100, 150), -30.0, 1e-4);  // 50 m from the end, 850 m along the path
  EXPECT_EQ(h->at(30, 150), 0.0f);            // inside the L, far from both legs
  EXPECT_EQ(h->at(180, 100), 0.0f);
}

TEST(Canyon, RefusesAPathOfOnePoint) {
  CanyonParams p;
  p.path = {{300, 300}, {300, 300}};
  const std::string e = error_of([&] { check_canyon(p); });
  EXPECT_NE(e.find("path"), std::string::npos) << e;
  EXPECT_NE(e.find("length"), std::string::npos) << e;
}

TEST(Canyon, RefusesAVerticalWall) {
  CanyonParams p;
  p.wall_slope = 90.0;
  const std::string e = error_of([&] { check_canyon(p); });
  EXPECT_NE(e.find("wall_slope"), std::string::npos) << e;
}

// ---- Dunes ----

// Column positions (m) of the crests along row j: local maxima above half the height.
std::vector<double> crests(const Heightfield& h, int j, double height) {
  std::vector<double> out;
  for (int i = 1; i + 1 < h.width(); ++i)
    if (h.at(i, j) > 0.5 * height && h.at(i, j) >= h.at(i - 1, j) && h.at(i, j) > h.at(i + 1, j))
      out.push_back(h.domain.x(i));
  return out;
}

double mean_spacing(const std::vector<double>& c) { return (c.back() - c.front()) / static_cast<double>(c.size() - 1); }

TEST(Dunes, CrestSpacingIsTheWavelengthAlongTheWind) {
  const Domain d = Domain::from_extent({0, 0}, {3000, 600}, {3001, 61});  // 1 m along x
  for (double sinuosity : {0.0, 30.0}) {
    const auto h = run_field("Dunes", d,
                             {{"wavelength", 100.0},
                              {"height", 8.0},
                              {"wind_azimuth", 90.0},
                              {"sinuosity", sinuosity},
                              {"seed", std::uint64_t{5}}});
    for (int j : {0, 30, 60}) {
      const auto c = crests(*h, j, 8.0);
      ASSERT_GE(c.size(), 20u);
      EXPECT_NEAR(mean_spacing(c), 100.0, 10.0) << "sinuosity " << sinuosity << ", row " << j;
    }
  }
}

TEST(Dunes, SlipFaceDownwindSteeperThanStossAndAtMostTheReposeAngle) {
  // Wind toward north (+y): along each column the lee faces +y. A tall dune whose slip face is held at repose.
  const Domain d = Domain::from_extent({0, 0}, {40, 1000}, {41, 2001});  // 0.5 m along y
  for (double height : {8.0, 20.0}) {
    const auto h = run_field(
        "Dunes", d,
        {{"wavelength", 100.0}, {"height", height}, {"wind_azimuth", 0.0}, {"stoss_share", 0.9}, {"sinuosity", 0.0}});
    double stoss = 0.0, lee = 0.0;  // steepest rise and fall going downwind, degrees
    for (int j = 0; j + 1 < 2001; ++j) {
      const double g = (h->at(20, j + 1) - h->at(20, j)) / 0.5;
      stoss = std::max(stoss, std::atan(g) / kDeg);
      lee = std::max(lee, std::atan(-g) / kDeg);
    }
    EXPECT_GT(lee, stoss + 5.0) << height;
    EXPECT_LE(lee, 34.0 + 0.1) << height;
    if (height == 20.0) EXPECT_NEAR(lee, 34.0, 0.1);  // 20 m over 10 m would be 63 degrees: held at repose
  }
  // The other wind: the lee faces -y, so rising toward +y is now the steep side.
  const auto back = run_field("Dunes", d, {{"wind_azimuth", 180.0}, {"sinuosity", 0.0}});
  double up = 0.0, down = 0.0;
  for (int j = 0; j + 1 < 2001; ++j) {
    const double g = back->at(20, j + 1) - back->at(20, j);
    up = std::max(up, g);
    down = std::max(down, -g);
  }
  EXPECT_GT(up, down);
}

TEST(Dunes, RefusesDunesTooTallForTheirWavelength) {
  const std::string e = error_of([] { run_field("Dunes", square(), {{"wavelength", 50.0}, {"height", 40.0}}); });
  EXPECT_NE(e.find("Dunes"), std::string::npos) << e;
  EXPECT_NE(e.find("height"), std::string::npos) << e;
}

// ---- Mountain ----

TEST(Mountain, SummitAtHeightEnvelopeBoundsTheRidgesAndZeroBeyond) {
  const Domain d = square();
  const auto smooth = run_field(
      "Mountain", d, {{"position", glm::dvec2(500, 500)}, {"radius", 400.0}, {"height", 300.0}, {"roughness", 0.0}});
  EXPECT_FLOAT_EQ(smooth->at(100, 100), 300.0f);
  EXPECT_NEAR(smooth->at(140, 100), 300.0 * 0.25 * 1.5, 1e-3);  // u = 0.5: (0.5)^2 (1 + 0.5)
  EXPECT_EQ(smooth->at(180, 100), 0.0f);

  const std::map<std::string, ParamValue> p{{"position", glm::dvec2(500, 500)},
                                            {"radius", 400.0},
                                            {"height", 300.0},
                                            {"roughness", 200.0},
                                            {"feature_size", 200.0},
                                            {"seed", std::uint64_t{11}}};
  const auto h = run_field("Mountain", d, p);
  EXPECT_NEAR(h->at(100, 100), 300.0, 1e-2);  // the noise is taken relative to the summit's
  double deviation = 0.0;
  for (int j = 0; j < 201; ++j)
    for (int i = 0; i < 201; ++i) {
      const double e = smooth->at(i, j) / 300.0;  // the envelope
      ASSERT_LE(std::abs(h->at(i, j) - smooth->at(i, j)), 200.0 * e + 1e-3) << i << "," << j;
      if (e == 0.0) ASSERT_EQ(h->at(i, j), 0.0f);
      deviation = std::max(deviation, static_cast<double>(std::abs(h->at(i, j) - smooth->at(i, j))));
    }
  EXPECT_GT(deviation, 30.0);  // the ridges are there
  EXPECT_TRUE(bit_identical(run_field("Mountain", d, p)->data, h->data));
  auto other = p;
  other["seed"] = std::uint64_t{12};
  EXPECT_FALSE(bit_identical(run_field("Mountain", d, other)->data, h->data));
}

TEST(Mountain, RefusesTooManyOctaves) {
  MountainParams p;
  p.octaves = 13;
  const std::string e = error_of([&] { check_mountain(p); });
  EXPECT_NE(e.find("octaves"), std::string::npos) << e;
}

// ---- Every landform: tiles join bit for bit ----

class LandformTiles : public testing::TestWithParam<std::string> {};

TEST_P(LandformTiles, ASubDomainEqualsTheCropOfTheFullDomain) {
  const Domain full = Domain::from_extent({-137.5, 211.25}, {1200, 900}, {241, 181});
  const auto whole = run_field(GetParam(), full, {});
  for (const auto& [i0, j0, w, h] : {std::array<int, 4>{37, 53, 91, 67}, {0, 0, 1, 1}, {200, 120, 41, 61}}) {
    const Domain sub = full.subdomain(i0, j0, w, h);
    const auto part = run_field(GetParam(), sub, {});
    std::vector<float> crop;
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) crop.push_back(whole->at(i0 + i, j0 + j));
    EXPECT_TRUE(bit_identical(part->data, crop)) << GetParam() << " at " << i0 << "," << j0;
  }
  // Not a trivial field: the defaults make a shape within this domain.
  float lo = whole->data[0], hi = whole->data[0];
  for (float v : whole->data) lo = std::min(lo, v), hi = std::max(hi, v);
  EXPECT_GT(hi - lo, 5.0f) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Landforms, LandformTiles,
                         testing::Values("Mountain", "Ridge", "Volcano", "Crater", "Canyon", "Dunes", "Plateau"));

}  // namespace
}  // namespace orogen
