// Promise tests of graphs/voronoi_island.json (S. Weiss 2015, Procedural Terrain) on the graph's
// real outputs at a reduced resolution: biomes consistent with elevation (through the lapse-rate
// temperature) and moisture by the Whittaker-style table, rivers that run down to the sea, pipe-model
// erosion that changed the terrain, vegetation only on land with the species its biome allows.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "support/run_process.h"
#include "support/seed_graphs.h"
#include "support/test_paths.h"

namespace orogen::test {
namespace {

// The table of the graph's Biomes node, retyped from A. Patel (2010) as the graph uses it: water first, then
// the elevation zones by temperature band (< 0, 0..8, 8..16, >= 16 deg C) and moisture sixths. Names in the
// order the Biomes node numbers them (first appearance).
const char* kNames[] = {"water",
                        "scorched",
                        "bare",
                        "tundra",
                        "snow",
                        "temperate_desert",
                        "shrubland",
                        "taiga",
                        "grassland",
                        "temperate_deciduous_forest",
                        "temperate_rain_forest",
                        "subtropical_desert",
                        "tropical_seasonal_forest",
                        "tropical_rain_forest"};

int expected_biome(bool wet, double t, double m) {
  if (wet) return 0;
  if (t < 0) return m < 1.0 / 6 ? 1 : m < 2.0 / 6 ? 2 : m < 3.0 / 6 ? 3 : 4;
  if (t < 8) return m < 2.0 / 6 ? 5 : m < 4.0 / 6 ? 6 : 7;
  if (t < 16) return m < 1.0 / 6 ? 5 : m < 3.0 / 6 ? 8 : m < 5.0 / 6 ? 9 : 10;
  return m < 1.0 / 6 ? 11 : m < 2.0 / 6 ? 8 : m < 4.0 / 6 ? 12 : 13;
}

// Distance of (t, m) to the nearest cell edge of the table (rounding at an edge may go either way).
bool near_edge(double t, double m) {
  for (double e : {0.0, 8.0, 16.0})
    if (std::abs(t - e) < 1e-3) return true;
  for (int k = 1; k < 6; ++k)
    if (std::abs(m - k / 6.0) < 1e-4) return true;
  return false;
}

class IslandSeed : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { run_ = new SeedRun(run_seed_graph("voronoi_island.json", "128")); }
  static void TearDownTestSuite() { delete run_; }
  static SeedRun* run_;
  std::filesystem::path file(const std::string& name) const { return run_->out / "voronoi_island" / name; }
};
SeedRun* IslandSeed::run_ = nullptr;

TEST_F(IslandSeed, BiomeTableMatchesTheGraph) {
  ASSERT_TRUE(run_->ok()) << run_->error;
  // The ids the test assumes are those the Biomes node reports.
  const auto& biomes = run_->stats["reports"]["biomes"]["report"]["biomes"];
  ASSERT_EQ(biomes.size(), std::size(kNames));
  for (std::size_t k = 0; k < biomes.size(); ++k) EXPECT_EQ(biomes[k]["name"], kNames[k]) << k;
}

TEST_F(IslandSeed, EveryCellHasTheBiomeOfItsElevationAndMoisture) {
  ASSERT_TRUE(run_->ok()) << run_->error;
  const auto height = read_raster(file("height.exr"));
  const auto temperature = read_raster(file("temperature.exr"));
  const auto moisture = read_raster(file("moisture.exr"));
  const auto wet = read_raster(file("water_mask.exr"));
  const auto biome = read_raster(file("biome_id.exr"));
  ASSERT_EQ(height.width, 128);
  ASSERT_EQ(biome.v.size(), height.v.size());
  // Temperature is the lapse rate applied to the eroded elevation: T = (T_dec + T_jun) / 2 - lapse z / 1000.
  const auto& tp = node_params(run_->graph, "temperature");
  const double t0 = 0.5 * (tp["t_december"].get<double>() + tp["t_june"].get<double>());
  const double lapse = tp["lapse_rate"].get<double>();
  std::set<int> seen;
  int land = 0, sea = 0, checked = 0;
  for (std::size_t k = 0; k < height.v.size(); ++k) {
    const double z = height.v[k];
    ASSERT_NEAR(temperature.v[k], t0 - lapse * z / 1000.0, 1e-3) << "cell " << k;
    ASSERT_GE(moisture.v[k], 0.0);
    ASSERT_LE(moisture.v[k], 1.0);
    const bool is_wet = wet.v[k] > 0.5;
    // Water is the sea (below 0.5 m) or the map's lakes; the sea is always water.
    if (z < 0.5) ASSERT_TRUE(is_wet) << "cell " << k << " at " << z << " m is not water";
    is_wet ? ++sea : ++land;
    seen.insert(static_cast<int>(biome.v[k]));
    if (!is_wet && near_edge(temperature.v[k], moisture.v[k])) continue;
    ++checked;
    ASSERT_EQ(static_cast<int>(biome.v[k]), expected_biome(is_wet, temperature.v[k], moisture.v[k]))
        << "cell " << k << ": z " << z << " m, T " << temperature.v[k] << " C, moisture " << moisture.v[k];
  }
  EXPECT_GT(land, 1000);
  EXPECT_GT(sea, 1000);
  EXPECT_GT(checked, static_cast<int>(height.v.size()) * 9 / 10);
  // An island of 900 m under the graph's climate spans at least two temperature zones and several biomes.
  EXPECT_GE(seen.size(), 5u);
}

TEST_F(IslandSeed, RiversRunDownToTheSea) {
  ASSERT_TRUE(run_->ok()) << run_->error;
  const auto rivers = nlohmann::json::parse(read_text(file("rivers.json")));
  const auto height = read_raster(file("height.exr"));
  const auto& features = rivers["features"];
  ASSERT_GT(features.size(), 10u);
  const double size = run_->graph["domain"]["size"][0].get<double>();
  const double spacing = size / (height.width - 1);
  auto sea_near = [&](double x, double y) {
    // Any sample within two spacings of (x, y) in the sea of the graph (below 0.5 m; row 0 is the northern row).
    const int ci = static_cast<int>(std::lround(x / spacing)),
              cj = height.height - 1 - static_cast<int>(std::lround(y / spacing));
    for (int j = std::max(0, cj - 2); j <= std::min(height.height - 1, cj + 2); ++j)
      for (int i = std::max(0, ci - 2); i <= std::min(height.width - 1, ci + 2); ++i)
        if (height.at(i, j) < 0.5) return true;
    return false;
  };
  std::vector<int> parent(features.size());
  for (std::size_t c = 0; c < features.size(); ++c) {
    const auto& f = features[c];
    parent[c] = f["properties"]["parent"].get<int>();
    const auto& pts = f["geometry"]["coordinates"];
    ASSERT_GE(pts.size(), 2u);
    // Downstream, a river never climbs.
    for (std::size_t k = 1; k < pts.size(); ++k)
      ASSERT_LE(pts[k][2].get<double>(), pts[k - 1][2].get<double>() + 1e-3) << "river " << c << " climbs at " << k;
    const auto& last = pts[pts.size() - 1];
    if (parent[c] < 0) {
      // A river without a parent ends at the coast (elevation 0), next to the sea of the final terrain.
      EXPECT_NEAR(last[2].get<double>(), 0.0, 1e-3) << "river " << c;
      EXPECT_TRUE(sea_near(last[0].get<double>(), last[1].get<double>()))
          << "river " << c << " ends at (" << last[0] << ", " << last[1] << ") away from the sea";
    } else {
      // Otherwise it ends where its parent begins (a confluence) and the chain of parents reaches the coast.
      ASSERT_LT(parent[c], static_cast<int>(features.size()));
      const auto& first = features[static_cast<std::size_t>(parent[c])]["geometry"]["coordinates"][0];
      EXPECT_NEAR(
          std::hypot(last[0].get<double>() - first[0].get<double>(), last[1].get<double>() - first[1].get<double>()),
          0.0, 1e-2)
          << "river " << c;
    }
  }
  for (std::size_t c = 0; c < features.size(); ++c) {
    int p = static_cast<int>(c), steps = 0;
    while (parent[static_cast<std::size_t>(p)] >= 0 && steps++ < static_cast<int>(features.size()))
      p = parent[static_cast<std::size_t>(p)];
    EXPECT_LT(parent[static_cast<std::size_t>(p)], 0) << "river " << c << " never reaches the sea (a cycle)";
  }
}

TEST_F(IslandSeed, PipeErosionChangedTheLandAndVegetationGrowsOnlyOnLand) {
  ASSERT_TRUE(run_->ok()) << run_->error;
  const auto before = read_raster(file("height_before_erosion.exr"));
  const auto after = read_raster(file("height.exr"));
  double moved = 0;
  for (std::size_t k = 0; k < before.v.size(); ++k) moved += std::abs(after.v[k] - before.v[k]);
  EXPECT_GT(moved / static_cast<double>(before.v.size()), 1e-4) << "erosion left the terrain unchanged";

  // Every plant stands above the sea, in a biome of one of the four samples around it (BiomeScatter looks the
  // biome up at its cell), never water, and of a species its biome allows (the graph's BiomeScatter table).
  const auto biome = read_raster(file("biome_id.exr"));
  std::map<int, std::set<int>> allowed;
  for (const auto& row : node_params(run_->graph, "vegetation")["species"])
    allowed[row["biome"].get<int>()].insert(row["class"].get<int>());
  const auto plants = read_csv(file("vegetation.csv"));
  const auto& x = plants.at("x");
  ASSERT_GT(x.size(), 100u);
  const double size = run_->graph["domain"]["size"][0].get<double>();
  const double spacing = size / (biome.width - 1);
  for (std::size_t k = 0; k < x.size(); ++k) {
    const int b = static_cast<int>(plants.at("biome")[k]);
    const int i = static_cast<int>(std::floor(x[k] / spacing));
    const int j = static_cast<int>(std::floor(plants.at("y")[k] / spacing));
    bool around = false;
    for (int dj = 0; dj <= 1; ++dj)
      for (int di = 0; di <= 1; ++di) {
        const int ii = std::clamp(i + di, 0, biome.width - 1), jj = std::clamp(j + dj, 0, biome.height - 1);
        around = around || static_cast<int>(biome.at(ii, biome.height - 1 - jj)) == b;
      }
    ASSERT_TRUE(around) << "plant " << k << " of biome " << b << " at (" << x[k] << ", " << plants.at("y")[k] << ")";
    ASSERT_GT(plants.at("z")[k], 0.0) << "plant " << k << " under the sea";
    ASSERT_NE(b, 0) << "plant " << k << " in the water";
    ASSERT_TRUE(allowed[b].count(static_cast<int>(plants.at("class")[k]))) << "plant " << k << " of biome " << b;
  }
}

}  // namespace
}  // namespace orogen::test
