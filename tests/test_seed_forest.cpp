// Promise tests of graphs/forest.json (L. Potter 2017, Generating a virtual forest environment using
// procedural content generation) on the graph's real outputs at a reduced resolution: Poisson-disk minimum
// distances per class radius, trees spaced by the life cycle's competition rule, ages within the maximum age,
// shade-loving undergrowth in the crowns' shadow and sun-loving flowers out of it for the sun of the chosen
// latitude, day and hour (recomputed here by brute force over every crown), rocks on the rock layer.
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include <gtest/gtest.h>

#include "support/seed_graphs.h"

namespace orogen::test {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct P {
  double x, y, z, s;
  int cls;
};

class ForestSeed : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    run_ = new SeedRun(run_seed_graph("forest.json", "129"));
    if (run_->out.empty()) return;
    const auto csv = read_csv(run_->out / "forest" / "points.csv");
    points_ = new std::vector<P>;
    for (std::size_t k = 0; k < csv.at("x").size(); ++k)
      points_->push_back(
          {csv.at("x")[k], csv.at("y")[k], csv.at("z")[k], csv.at("sx")[k], static_cast<int>(csv.at("class")[k])});
    ages_ = new std::vector<double>(csv.at("age"));
  }
  static void TearDownTestSuite() {
    delete run_;
    delete points_;
    delete ages_;
  }
  static std::vector<P> of_class(int c) {
    std::vector<P> out;
    for (const auto& p : *points_)
      if (p.cls == c) out.push_back(p);
    return out;
  }
  static SeedRun* run_;
  static std::vector<P>* points_;
  static std::vector<double>* ages_;
};
SeedRun* ForestSeed::run_ = nullptr;
std::vector<P>* ForestSeed::points_ = nullptr;
std::vector<double>* ForestSeed::ages_ = nullptr;

// The closest pair distance of a point set relative to a required distance: min over pairs of d / need(i, j).
template <class Need>
double min_ratio(const std::vector<P>& pts, double reach, Need need) {
  std::map<std::pair<long, long>, std::vector<int>> grid;
  for (int i = 0; i < static_cast<int>(pts.size()); ++i)
    grid[{std::lround(std::floor(pts[i].x / reach)), std::lround(std::floor(pts[i].y / reach))}].push_back(i);
  double worst = 1e9;
  for (int i = 0; i < static_cast<int>(pts.size()); ++i) {
    const long cx = std::lround(std::floor(pts[i].x / reach)), cy = std::lround(std::floor(pts[i].y / reach));
    for (long gy = cy - 1; gy <= cy + 1; ++gy)
      for (long gx = cx - 1; gx <= cx + 1; ++gx) {
        const auto it = grid.find({gx, gy});
        if (it == grid.end()) continue;
        for (int j : it->second)
          if (j > i)
            worst = std::min(worst, std::hypot(pts[i].x - pts[j].x, pts[i].y - pts[j].y) / need(pts[i], pts[j]));
      }
  }
  return worst;
}

TEST_F(ForestSeed, PoissonClassesKeepTheirRadii) {
  ASSERT_TRUE(run_->ok()) << run_->error;
  ASSERT_NE(points_, nullptr);
  int checked = 0;
  for (const auto& node : run_->graph["nodes"]) {
    if (node["type"] != "PoissonDisk") continue;
    const auto& p = node["params"];
    const int first = p.value("first_class", 0), count = p.value("class_count", 1);
    for (int k = 0; k < count; ++k) {
      const int cls = first + k;
      if (cls <= 1) continue;  // the tree seedlings: the life cycle moves them (next test)
      const double r = p["radius_" + std::to_string(k)].get<double>();
      const auto pts = of_class(cls);
      ASSERT_GT(pts.size(), 20u) << "class " << cls;
      EXPECT_GE(min_ratio(pts, r, [&](const P&, const P&) { return r; }), 1.0 - 1e-5)
          << "class " << cls << " (node " << node["id"] << ") has points closer than its radius " << r << " m";
      ++checked;
    }
  }
  EXPECT_EQ(checked, 3);  // rocks, ferns, flowers
}

TEST_F(ForestSeed, TreesAreSpacedByCompetitionAndAgedWithinTheirLifespan) {
  ASSERT_TRUE(run_->ok()) << run_->error;
  ASSERT_NE(points_, nullptr);
  const auto& lc = node_params(run_->graph, "forest");
  const double competition = lc["competition"].get<double>(), max_age = lc["max_age"].get<double>();
  const double maturity = lc["maturity_age"].get<double>();
  const double s0 = lc["min_scale"].get<double>(), s1 = lc["max_scale"].get<double>();
  std::vector<P> trees;
  for (std::size_t k = 0; k < points_->size(); ++k) {
    const auto& p = (*points_)[k];
    if (p.cls > 1) continue;
    trees.push_back(p);
    const double age = (*ages_)[k];
    ASSERT_GE(age, 0.0) << "tree " << k;
    ASSERT_LE(age, max_age) << "tree " << k << " outlived the maximum age";
    ASSERT_NEAR(p.s, s0 + std::clamp(age / maturity, 0.0, 1.0) * (s1 - s0), 1e-5) << "tree " << k;
  }
  ASSERT_GT(trees.size(), 100u);
  EXPECT_GE(min_ratio(trees, competition * s1, [&](const P& a, const P& b) { return competition * 0.5 * (a.s + b.s); }),
            1.0 - 1e-5);
}

TEST_F(ForestSeed, ShadeLovingPlantsStandInShadowAndOthersInTheSun) {
  ASSERT_TRUE(run_->ok()) << run_->error;
  ASSERT_NE(points_, nullptr);
  const auto& sp = node_params(run_->graph, "undergrowth");
  const auto& fp = node_params(run_->graph, "flowers");
  ASSERT_EQ(sp["sun"], "time");
  for (const char* key : {"latitude", "day_of_year", "hour", "crown_radius", "crown_height"})
    ASSERT_EQ(sp[key], fp[key]) << key;
  // The sun for the latitude, day and solar hour: Cooper's declination, hour angle 15 deg/h from noon.
  const double phi = sp["latitude"].get<double>() * kDeg;
  const double delta =
      23.45 * std::sin(2 * std::numbers::pi * (284.0 + sp["day_of_year"].get<double>()) / 365.0) * kDeg;
  const double h = 15.0 * (sp["hour"].get<double>() - 12.0) * kDeg;
  const double sin_alt = std::sin(phi) * std::sin(delta) + std::cos(phi) * std::cos(delta) * std::cos(h);
  ASSERT_GT(sin_alt, 0.05) << "the graph's sun is under the horizon";
  const double alt = std::asin(sin_alt);
  // Azimuth clockwise from north, afternoon in the west.
  double az = std::acos(
      std::clamp((std::sin(delta) - std::sin(alt) * std::sin(phi)) / (std::cos(alt) * std::cos(phi)), -1.0, 1.0));
  if (h > 0) az = 2 * std::numbers::pi - az;
  const double ux = std::sin(az) * std::cos(alt), uy = std::cos(az) * std::cos(alt), uz = sin_alt;

  const double cr = sp["crown_radius"].get<double>(), ch = sp["crown_height"].get<double>();
  std::vector<P> trees = of_class(0), conifers = of_class(1);
  trees.insert(trees.end(), conifers.begin(), conifers.end());
  // Miss distance of the ray toward the sun from q to the nearest crown, minus its radius (< 0: shaded).
  auto margin = [&](const P& q) {
    double best = 1e9;
    for (const auto& t : trees) {
      const double r = cr * t.s;
      const double cx = t.x - q.x, cy = t.y - q.y, cz = t.z + ch * t.s - q.z;
      const double along = std::max(0.0, cx * ux + cy * uy + cz * uz);
      const double dx = cx - along * ux, dy = cy - along * uy, dz = cz - along * uz;
      best = std::min(best, std::sqrt(dx * dx + dy * dy + dz * dz) - r);
    }
    return best;
  };
  const auto ferns = of_class(3), flowers = of_class(4);
  ASSERT_GT(ferns.size(), 50u);
  ASSERT_GT(flowers.size(), 50u);
  int wrong = 0;
  for (const auto& q : ferns)
    if (margin(q) > 1e-3) ++wrong;
  EXPECT_EQ(wrong, 0) << "shade-loving ferns in the sun";
  wrong = 0;
  for (const auto& q : flowers)
    if (margin(q) < -1e-3) ++wrong;
  EXPECT_EQ(wrong, 0) << "sun-loving flowers in the shade";
}

TEST_F(ForestSeed, RocksLieOnTheRockLayer) {
  ASSERT_TRUE(run_->ok()) << run_->error;
  ASSERT_NE(points_, nullptr);
  const auto dominant = read_raster(run_->out / "forest" / "dominant.png");  // 0..1 for layers 0..2
  const double size = run_->graph["domain"]["size"][0].get<double>();
  const double spacing = size / (dominant.width - 1);
  const auto rocks = of_class(2);
  ASSERT_GT(rocks.size(), 20u);
  int on_rock = 0;
  for (const auto& r : rocks) {
    const int i = static_cast<int>(std::lround(r.x / spacing));
    const int j = dominant.height - 1 - static_cast<int>(std::lround(r.y / spacing));
    if (std::lround(dominant.at(i, j) * 2.0) == 2) ++on_rock;
  }
  // The mask is the rock weight >= 0.5 (bilinear); the nearest sample's dominant layer agrees almost always.
  EXPECT_GT(on_rock, static_cast<int>(rocks.size()) * 9 / 10);
}

}  // namespace
}  // namespace orogen::test
