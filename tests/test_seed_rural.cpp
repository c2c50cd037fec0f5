// Promise tests of graphs/rural_resources.json (H. Long 2016, Using procedural methods to generate
// realistic virtual rural worlds) on the graph's real outputs at a reduced resolution: lit hours within the
// day's length (0..24 h a day, at most 8760 h a year), temperatures that are the seasonal curve minus the
// lapse rate (within the bounds the terrain's altitudes allow), k clusters covering the map, a water flow that
// conserves its water and a flood-filled lake with a flat surface.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <set>

#include <gtest/gtest.h>

#include "support/seed_graphs.h"

namespace orogen::test {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr const char* kMonths[12] = {"jan", "feb", "mar", "apr", "may", "jun",
                                     "jul", "aug", "sep", "oct", "nov", "dec"};
constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};

// Long (2016) eq. 3.3 with June as the northern summer: 23.5 deg in June, -23.5 in December.
double declination(int month) { return 23.5 - std::abs(6 - month) * 23.5 / 3.0; }
// Hours between sunrise and sunset on a flat horizon (Duffie and Beckman 2013, eq. 1.6.10).
double day_length(double latitude, double decl) {
  const double c = -std::tan(latitude * kDeg) * std::tan(decl * kDeg);
  if (c <= -1.0) return 24.0;
  if (c >= 1.0) return 0.0;
  return 2.0 * std::acos(c) / kDeg / 15.0;
}
// Long (2016) eq. 3.4.
double base_temperature(double t_dec, double t_jun, int month) {
  return t_dec + (6.0 - std::abs(6 - month)) / 6.0 * (t_jun - t_dec);
}

class RuralSeed : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { run_ = new SeedRun(run_seed_graph("rural_resources.json", "128")); }
  static void TearDownTestSuite() { delete run_; }
  static SeedRun* run_;
  std::filesystem::path file(const std::string& name) const { return run_->out / "rural_resources" / name; }
};
SeedRun* RuralSeed::run_ = nullptr;

TEST_F(RuralSeed, LitHoursWithinTheDayAndTheYear) {
  ASSERT_TRUE(run_->ok()) << run_->error;
  const double latitude = node_params(run_->graph, "sun")["latitude"].get<double>();
  const auto height = read_raster(file("height.exr"));
  ASSERT_EQ(height.width, 128);
  std::vector<double> yearly(height.v.size(), 0.0);
  double max_day_length_year = 0.0;
  int shadowed = 0;
  for (int m = 1; m <= 12; ++m) {
    const auto hours = read_raster(file("lit_hours.exr"), kMonths[m - 1]);
    ASSERT_EQ(hours.v.size(), height.v.size());
    const double day = day_length(latitude, declination(m));
    max_day_length_year += kDays[m - 1] * day;
    for (std::size_t k = 0; k < hours.v.size(); ++k) {
      const double h = hours.v[k];
      ASSERT_GE(h, 0.0) << "month " << m << " cell " << k;
      ASSERT_LE(h, 24.0) << "month " << m << " cell " << k;
      // Never more than the time the sun is above a flat horizon.
      ASSERT_LE(h, day + 1e-3) << "month " << m << " cell " << k;
      if (h < day - 0.5) ++shadowed;
      yearly[k] += kDays[m - 1] * h;
    }
  }
  for (std::size_t k = 0; k < yearly.size(); ++k) {
    ASSERT_LE(yearly[k], 8760.0) << "cell " << k;
    ASSERT_LE(yearly[k], max_day_length_year + 1.0) << "cell " << k;
  }
  // The hills do cast shadows (a flat-horizon day everywhere would mean no shadowing at all).
  EXPECT_GT(shadowed, 100);
  // And the sunniest cell gets most of the astronomical maximum (~4380 h a year away from the poles).
  EXPECT_GT(*std::max_element(yearly.begin(), yearly.end()), 0.8 * max_day_length_year);
}

TEST_F(RuralSeed, TemperaturesFollowTheSeasonAndTheLapseRate) {
  ASSERT_TRUE(run_->ok()) << run_->error;
  const auto& p = node_params(run_->graph, "temperature");
  const double t_dec = p["t_december"].get<double>(), t_jun = p["t_june"].get<double>();
  const double lapse = p["lapse_rate"].get<double>() / 1000.0, gain = p["illumination_gain"].get<double>();
  const double ref_hours = p["reference_hours"].get<double>();
  const double ref_alt = p.contains("reference_altitude") ? p["reference_altitude"].get<double>() : 0.0;
  const auto height = read_raster(file("height.exr"));
  const auto [zmin_it, zmax_it] = std::minmax_element(height.v.begin(), height.v.end());
  const double zmin = *zmin_it, zmax = *zmax_it;
  ASSERT_GT(zmax - zmin, 100.0);
  for (int m = 1; m <= 12; ++m) {
    const auto t = read_raster(file("temperature.exr"), kMonths[m - 1]);
    const auto hours = read_raster(file("lit_hours.exr"), kMonths[m - 1]);
    const double base = base_temperature(t_dec, t_jun, m);
    // Physical bounds: the seasonal temperature at the reference altitude, cooled by the lapse rate between
    // the highest and the lowest cell, warmed or cooled by the sun term between 0 and 24 lit hours.
    const double lo = base - lapse * (zmax - ref_alt) + std::min(gain * (0 - ref_hours), gain * (24 - ref_hours));
    const double hi = base - lapse * (zmin - ref_alt) + std::max(gain * (0 - ref_hours), gain * (24 - ref_hours));
    double tmin = 1e9, tmax = -1e9;
    for (std::size_t k = 0; k < t.v.size(); ++k) {
      ASSERT_GE(t.v[k], lo - 1e-3) << "month " << m << " cell " << k;
      ASSERT_LE(t.v[k], hi + 1e-3) << "month " << m << " cell " << k;
      // And per cell exactly: T = T(m) - lapse (z - z_ref) + gain (hours - reference hours).
      ASSERT_NEAR(t.v[k], base - lapse * (height.v[k] - ref_alt) + gain * (hours.v[k] - ref_hours), 1e-3)
          << "month " << m << " cell " << k;
      tmin = std::min(tmin, t.v[k]);
      tmax = std::max(tmax, t.v[k]);
    }
    // The spread within a month is at least the lapse rate over the relief less the sun term's range.
    EXPECT_GT(tmax - tmin, lapse * (zmax - zmin) - 24.0 * std::abs(gain)) << "month " << m;
  }
}

TEST_F(RuralSeed, KClustersCoverTheMap) {
  ASSERT_TRUE(run_->ok()) << run_->error;
  const int k = node_params(run_->graph, "clusters")["k"].get<int>();
  const auto ids = read_raster(file("cluster_id.exr"));
  std::vector<std::int64_t> counts(static_cast<std::size_t>(k), 0);
  for (std::size_t c = 0; c < ids.v.size(); ++c) {
    const double id = ids.v[c];
    ASSERT_EQ(id, std::floor(id)) << "cell " << c << " has no integer label";
    ASSERT_GE(id, 0) << "cell " << c;
    ASSERT_LT(id, k) << "cell " << c;
    ++counts[static_cast<std::size_t>(id)];
  }
  for (int c = 0; c < k; ++c) EXPECT_GT(counts[static_cast<std::size_t>(c)], 0) << "cluster " << c << " is empty";
  // The report agrees with the map, and Lloyd's iterations never increased the objective.
  const auto& report = run_->stats["reports"]["clusters"]["report"];
  ASSERT_EQ(report["clusters"].size(), static_cast<std::size_t>(k));
  std::int64_t total = 0;
  for (int c = 0; c < k; ++c) {
    EXPECT_EQ(report["clusters"][static_cast<std::size_t>(c)]["count"].get<std::int64_t>(),
              counts[static_cast<std::size_t>(c)]);
    total += counts[static_cast<std::size_t>(c)];
  }
  EXPECT_EQ(total, static_cast<std::int64_t>(ids.width) * ids.height);
  const auto& objective = report["objective"];
  for (std::size_t i = 1; i < objective.size(); ++i)
    EXPECT_LE(objective[i].get<double>(), objective[i - 1].get<double>() * (1 + 1e-9)) << "iteration " << i;
}

TEST_F(RuralSeed, WaterFlowConservesWaterAndTheFloodFilledLakeIsFlat) {
  ASSERT_TRUE(run_->ok()) << run_->error;
  const auto& balance = run_->stats["reports"]["water"]["report"];
  const double rain = balance["rain_m3"].get<double>();
  ASSERT_GT(rain, 0.0);
  const double accounted = balance["stored_m3"].get<double>() + balance["border_outflow_m3"].get<double>() +
                           balance["sink_inflow_m3"].get<double>();
  EXPECT_NEAR(accounted, rain, 1e-6 * rain);
  const auto water = read_raster(file("water_depth.exr"));
  for (std::size_t c = 0; c < water.v.size(); ++c) ASSERT_GE(water.v[c], 0.0) << "cell " << c;

  // The lake grown from the graph's seed point: a flat surface over every flooded cell, above the ground.
  const auto ground = read_raster(file("height.exr"));
  const auto surface = read_raster(file("flood_surface.exr"));
  const auto depth = read_raster(file("flood_depth.exr"));
  double level = std::nan(""), lo = 1e9;
  int flooded = 0;
  for (std::size_t c = 0; c < depth.v.size(); ++c) {
    if (depth.v[c] <= 0.0) {
      ASSERT_EQ(surface.v[c], ground.v[c]) << "cell " << c;
      continue;
    }
    ++flooded;
    if (std::isnan(level)) level = surface.v[c];
    ASSERT_NEAR(surface.v[c], level, 1e-3) << "cell " << c;
    ASSERT_NEAR(surface.v[c] - ground.v[c], depth.v[c], 1e-3) << "cell " << c;
    lo = std::min(lo, ground.v[c]);
  }
  EXPECT_GT(flooded, 50) << "the seed point of the flood fill lies in no depression";
  EXPECT_GT(level - lo, 1.0);
  // The seed point lies in the lake.
  const auto& seed = node_params(run_->graph, "lake")["position"];
  const double size = run_->graph["domain"]["size"][0].get<double>();
  const double spacing = size / (depth.width - 1);
  const int i = static_cast<int>(std::lround(seed[0].get<double>() / spacing));
  const int j = depth.height - 1 - static_cast<int>(std::lround(seed[1].get<double>() / spacing));
  EXPECT_GT(depth.at(i, j), 0.0);
}

}  // namespace
}  // namespace orogen::test
