// Climate family: sun geometry against analytic values, shadows against a brute-force ray march, the
// temperature curve and lapse rate, soil humidity and its weighted history, the resource stack.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include <tbb/global_control.h>

#include "evaluator/run_node.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/table_json.h"

#include <nlohmann/json.hpp>
#include "nodes/climate/biomes.h"
#include "nodes/climate/resources.h"
#include "nodes/climate/sun.h"
#include "support/key_checks.h"

namespace orogen::climate {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Heightfield make_field(int n, double spacing, double (*f)(double, double)) {
  Heightfield h(Domain::from_extent({0, 0}, {spacing * (n - 1), spacing * (n - 1)}, {n, n}));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) h.at(i, j) = static_cast<float>(f(h.domain.x(i), h.domain.y(j)));
  return h;
}

double hills(double x, double y) {
  return 120.0 * std::sin(x / 310.0) * std::cos(y / 270.0) + 60.0 * std::sin((x + 2.0 * y) / 190.0) + 0.05 * x;
}

TEST(Sun, EquinoxNoonElevationIsNinetyMinusLatitude) {
  for (double lat : {-60.0, -20.0, 0.0, 10.0, 45.0, 70.0}) {
    const glm::dvec3 s = sun_direction(lat, declination_deg(3), 12.0);
    EXPECT_NEAR(std::asin(s.z) / kDeg, 90.0 - std::abs(lat), 1e-9) << lat;
    EXPECT_NEAR(s.x, 0.0, 1e-12);
    if (lat > 0) {
      EXPECT_LT(s.y, 0.0) << "northern sun is due south at noon";
    }
    if (lat < 0) {
      EXPECT_GT(s.y, 0.0);
    }
  }
  // June solstice noon at 23.5 N: the sun at the zenith.
  EXPECT_NEAR(sun_direction(23.5, declination_deg(6), 12.0).z, 1.0, 1e-12);
  // Morning sun in the east, afternoon in the west.
  EXPECT_GT(sun_direction(45.0, 0.0, 9.0).x, 0.0);
  EXPECT_LT(sun_direction(45.0, 0.0, 15.0).x, 0.0);
}

TEST(Sun, DeclinationByMonth) {
  EXPECT_DOUBLE_EQ(declination_deg(6), 23.5);
  EXPECT_DOUBLE_EQ(declination_deg(12), -23.5);
  EXPECT_DOUBLE_EQ(declination_deg(3), 0.0);
  EXPECT_DOUBLE_EQ(declination_deg(9), 0.0);
  for (int k = 1; k <= 5; ++k) EXPECT_DOUBLE_EQ(declination_deg(6 - k), declination_deg(6 + k));
}

TEST(Sun, DayLengthEquatorPolarAndSixtyNorth) {
  for (int m = 1; m <= 12; ++m) EXPECT_NEAR(day_length_hours(0.0, declination_deg(m)), 12.0, 1e-9);
  const double tan60 = std::tan(60.0 * kDeg), tan235 = std::tan(23.5 * kDeg);
  EXPECT_NEAR(day_length_hours(60.0, 23.5), 2.0 / 15.0 * std::acos(-tan60 * tan235) / kDeg, 1e-9);
  EXPECT_NEAR(day_length_hours(60.0, -23.5), 2.0 / 15.0 * std::acos(tan60 * tan235) / kDeg, 1e-9);
  EXPECT_NEAR(day_length_hours(60.0, 23.5), 18.51, 0.02);
  EXPECT_NEAR(day_length_hours(60.0, -23.5), 5.49, 0.02);
  EXPECT_EQ(day_length_hours(80.0, 23.5), 24.0);  // polar day
  EXPECT_EQ(day_length_hours(80.0, -23.5), 0.0);  // polar night
  EXPECT_EQ(day_length_hours(-80.0, -23.5), 24.0);
  EXPECT_EQ(day_length_hours(90.0, 0.0), day_length_hours(90.0, 0.0));  // finite at the pole
}

TEST(Sun, FlatTerrainLitAllDaylightAndIrradianceIsCosZenith) {
  Heightfield flat(Domain::from_extent({0, 0}, {630, 630}, {64, 64}), 100.0f);
  for (double lat : {0.0, 45.0, 60.0, 80.0, -35.0}) {
    SunParams p;
    p.latitude = lat;
    std::vector<int> months;
    for (int m = 1; m <= 12; ++m) months.push_back(m);
    const auto d = sun_daily(flat, p, months);
    for (int m = 1; m <= 12; ++m) {
      const double len = day_length_hours(lat, declination_deg(m));
      // Mean irradiance over 24 h of a horizontal surface: integral of S cos(zenith) at the interval midpoints.
      double expect = 0.0;
      for (int k = 0; k < 24; ++k) {
        const double a = std::max(12.0 - len / 2, double(k)), b = std::min(12.0 + len / 2, k + 1.0);
        if (b > a)
          expect += (b - a) * p.irradiance * std::max(0.0, sun_direction(lat, declination_deg(m), 0.5 * (a + b)).z);
      }
      expect /= 24.0;
      for (int c : {0, 1000, 4095}) {
        EXPECT_NEAR(d.hours->data[std::size_t(c) * 12 + std::size_t(m - 1)], len, 1e-4) << lat << " " << m;
        EXPECT_NEAR(d.irradiance->data[std::size_t(c) * 12 + std::size_t(m - 1)], expect, 1e-2 * (1 + expect / 100))
            << lat << " " << m;
      }
    }
    for (double hour : {7.0, 10.5, 12.0, 16.0}) {
      const auto in = sun_instant(flat, p, 6, hour);
      const double cz = sun_direction(lat, declination_deg(6), hour).z;
      EXPECT_EQ(in.lit->at(30, 30), cz > 0 ? 1.0f : 0.0f);
      EXPECT_NEAR(in.direct->at(30, 30), std::max(0.0, cz) * p.irradiance, 1e-2);
    }
  }
}

TEST(Sun, TiltedPlaneIrradianceIsCosIncidence) {
  // A plane facing south at 30 degrees: at equinox noon at latitude 30 N the sun is normal to it.
  Heightfield plane(Domain::from_extent({0, 0}, {630, 630}, {64, 64}));
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) plane.at(i, j) = static_cast<float>(500.0 + std::tan(30.0 * kDeg) * plane.domain.y(j));
  SunParams p;
  p.latitude = 30.0;
  const auto in = sun_instant(plane, p, 3, 12.0);
  EXPECT_NEAR(in.direct->at(30, 30), p.irradiance, 0.5);
  EXPECT_EQ(in.lit->at(30, 30), 1.0f);
}

// Brute force: march from every cell toward the sun in small steps on the bilinear surface.
float marched_tangent(const Heightfield& z, int i, int j, glm::dvec2 dir) {
  const double step = 0.25 * std::min(z.domain.spacing.x, z.domain.spacing.y);
  const glm::dvec2 p0 = z.domain.position(i, j);
  const double z0 = z.at(i, j);
  float best = -std::numeric_limits<float>::infinity();
  for (double t = step;; t += step) {
    const glm::dvec2 q = p0 + t * dir;
    const glm::dvec2 s = z.domain.to_sample(q);
    if (s.x < 0 || s.y < 0 || s.x > z.width() - 1 || s.y > z.height() - 1) break;
    best = std::max(best, static_cast<float>((z.bilinear(s.x, s.y) - z0) / t));
  }
  return best;
}

TEST(Sun, HorizonSweepMatchesRayMarch) {
  // 10 m: a rough terrain for its grid (a few cells per hill flank); 5 m: the error must shrink.
  for (double spacing : {10.0, 5.0}) {
    const Heightfield z = make_field(96, spacing, hills);
    for (double az : {0.0, 17.0, 45.0, 90.0, 133.0, 200.0, 271.0, 333.0}) {
      const glm::dvec2 dir(std::sin(az * kDeg), std::cos(az * kDeg));  // azimuth clockwise from north
      const auto sweep = horizon_tangent(z, dir);
      int compared = 0, disagree = 0;
      double max_err = 0.0;
      for (int j = 0; j < 96; j += 3)
        for (int i = 0; i < 96; i += 3) {
          const float ref = marched_tangent(z, i, j, dir);
          const float got = sweep[z.index(i, j)];
          if (std::isinf(ref) || std::isinf(got)) {
            // Both see nothing ahead only at the border facing the sun; allow one cell of rounding there.
            continue;
          }
          ++compared;
          // Only horizons above the horizontal can shadow: compare max(0, angle).
          const double err = std::abs(std::atan(std::max(0.0f, got)) - std::atan(std::max(0.0f, ref))) / kDeg;
          max_err = std::max(max_err, err);
          // Cells take the horizon interpolated between the two lines beside them: allow 2 degrees.
          if (err > 2.0) ++disagree;
        }
      EXPECT_GT(compared, 800) << az;
      EXPECT_LE(disagree, compared / 100) << "azimuth " << az << " max error " << max_err << " deg";
      if (spacing == 5.0) {
        EXPECT_LT(max_err, 1.5) << "azimuth " << az;
      }
    }
  }
}

TEST(Sun, AxisAlignedHorizonIsExact) {
  const Heightfield z = make_field(64, 5.0, hills);
  for (glm::dvec2 dir : {glm::dvec2(1, 0), glm::dvec2(-1, 0), glm::dvec2(0, 1), glm::dvec2(0, -1)}) {
    const auto sweep = horizon_tangent(z, dir);
    for (int j = 1; j < 63; j += 5)
      for (int i = 1; i < 63; i += 5) {
        // Exact maximum over grid cells ahead along the axis.
        float best = -std::numeric_limits<float>::infinity();
        for (int k = 1;; ++k) {
          const int ii = i + k * int(dir.x), jj = j + k * int(dir.y);
          if (ii < 0 || jj < 0 || ii >= 64 || jj >= 64) break;
          best = std::max(best, static_cast<float>((double(z.at(ii, jj)) - z.at(i, j)) / (5.0 * k)));
        }
        EXPECT_NEAR(sweep[z.index(i, j)], best, 1e-5) << i << "," << j;
      }
  }
}

TEST(Sun, WallShadowsTheSideAwayFromTheSun) {
  // A 100 m wall running east-west across rows 40..41 of flat ground, 1 m spacing, +y north.
  Heightfield z(Domain::from_extent({0, 0}, {127, 127}, {128, 128}), 0.0f);
  for (int i = 0; i < 128; ++i) z.at(i, 40) = z.at(i, 41) = 100.0f;
  SunParams p;
  p.latitude = 45.0;  // equinox noon: elevation 45 deg, sun due south, shadow 100 m long to the north
  const auto noon = sun_instant(z, p, 3, 12.0);
  for (int j = 42; j < 128; ++j) {
    const double dist = j - 41.0;  // north of the wall's north face
    if (dist < 97.0) {
      EXPECT_EQ(noon.lit->at(64, j), 0.0f) << "row " << j << " must be in the wall's shadow";
    }
    if (dist > 103.0) {
      EXPECT_EQ(noon.lit->at(64, j), 1.0f) << "row " << j;
    }
  }
  for (int j = 0; j < 40; ++j) EXPECT_EQ(noon.lit->at(64, j), 1.0f) << "south of the wall is lit at noon";
  // In the southern hemisphere the noon sun is in the north: the shadow falls to the south.
  p.latitude = -45.0;
  const auto south = sun_instant(z, p, 9, 12.0);
  EXPECT_EQ(south.lit->at(64, 20), 0.0f);
  EXPECT_EQ(south.lit->at(64, 60), 1.0f);
  // Daily lit hours: the foot of the wall on the north side gets less sun than the south side.
  p.latitude = 45.0;
  const int months[] = {12};
  const auto d = sun_daily(z, p, months);
  EXPECT_LT(d.hours->data[z.index(64, 43)], d.hours->data[z.index(64, 38)]);
}

TEST(Sun, ConeSouthFaceLitAllDayNorthFaceDark) {
  // A 45-degree cone, 300 m high: in December at 45 N the sun never climbs above 21.5 degrees, so the north
  // face (45 degrees, facing away) never sees it and the south face sees it from sunrise to sunset.
  Heightfield z(Domain::from_extent({0, 0}, {1990, 1990}, {200, 200}));
  for (int j = 0; j < 200; ++j)
    for (int i = 0; i < 200; ++i)
      z.at(i, j) =
          static_cast<float>(std::max(0.0, 300.0 - std::hypot(z.domain.x(i) - 1000.0, z.domain.y(j) - 1000.0)));
  SunParams p;
  p.latitude = 45.0;
  const int months[] = {12, 6};
  const auto d = sun_daily(z, p, months);
  const double dec = day_length_hours(45.0, -23.5), jun = day_length_hours(45.0, 23.5);
  EXPECT_NEAR(d.hours->pixel(100, 85)[0], dec, 1e-4) << "south face, December";
  EXPECT_NEAR(d.hours->pixel(100, 115)[0], 0.0, 1e-4) << "north face, December";
  EXPECT_GT(d.hours->pixel(100, 115)[1], 0.5 * jun) << "north face, June (noon sun at 68.5 degrees)";
  EXPECT_NEAR(d.hours->pixel(10, 10)[0], dec, 1e-4) << "open plain";
  EXPECT_LT(d.hours->pixel(100, 140)[0], dec - 1.0) << "plain north of the cone: in its shadow part of the day";
  EXPECT_NEAR(d.hours->pixel(100, 60)[0], dec, 1e-4) << "plain south of the cone";
}

TEST(Sun, HighSunShortcutEqualsTheSweep) {
  // A gentle terrain (slopes under about 25 degrees) at 30 N in June: around noon the sun is above any
  // possible horizon and sun_daily skips the sweep; lit hours must equal the sweep's everywhere.
  Heightfield z = make_field(64, 10.0, hills);
  for (auto& v : z.data) v *= 0.25f;
  SunParams p;
  p.latitude = 30.0;
  const int months[] = {6};
  const auto d = sun_daily(z, p, months);
  const double decl = declination_deg(6), h0 = sunset_hour_angle_deg(30.0, decl) / 15.0;
  std::vector<float> hours(z.data.size(), 0.0f);
  for (int k = 0; k < 24; ++k) {
    const double a = std::max(12.0 - h0, double(k)), b = std::min(12.0 + h0, k + 1.0);
    if (!(b > a)) continue;
    const glm::dvec3 s = sun_direction(30.0, decl, 0.5 * (a + b));
    const auto th = horizon_tangent(z, {s.x, s.y});
    const float tan_e = static_cast<float>(s.z / std::hypot(s.x, s.y));
    for (std::size_t c = 0; c < hours.size(); ++c)
      if (tan_e > th[c]) hours[c] += static_cast<float>(b - a);
  }
  int shaded = 0;
  for (std::size_t c = 0; c < hours.size(); ++c) {
    ASSERT_EQ(d.hours->data[c], hours[c]) << c;
    shaded += hours[c] < 13.5f;
  }
  EXPECT_GT(shaded, 0) << "the low sun must still cast some shadows on this terrain";
}

TEST(Sun, BitIdenticalAcrossThreadCounts) {
  const Heightfield z = make_field(80, 10.0, hills);
  SunParams p;
  p.latitude = 52.0;
  p.time_step = 2.0;
  const int months[] = {1, 4, 6, 9};
  SunDaily a, b;
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    a = sun_daily(z, p, months);
  }
  {
    tbb::global_control many(tbb::global_control::max_allowed_parallelism, 4);
    b = sun_daily(z, p, months);
  }
  EXPECT_EQ(a.hours->data, b.hours->data);
  EXPECT_EQ(a.irradiance->data, b.irradiance->data);
}

TEST(Sun, NodeRunsAndKeys) {
  const Domain d = Domain::from_extent({0, 0}, {640, 640}, {33, 33});
  auto z = std::make_shared<Heightfield>(make_field(33, 20.0, hills));
  const auto r = run_node("SunIllumination", d, {}, {{"in", PortValue(HeightfieldPtr(z))}});
  const auto hours = r.get<Image>(0);
  EXPECT_EQ(hours->channels, 12);
  EXPECT_EQ(hours->channel_names[5], "jun");
  for (float v : hours->data) {
    EXPECT_GE(v, 0.0f);
    EXPECT_LE(v, 24.0f);
  }
  expect_every_param_changes_key("SunIllumination", d);
  expect_every_input_changes_key("SunIllumination", d);
}

TEST(Temperature, CurveEndpointsSymmetryAndLapseRate) {
  EXPECT_DOUBLE_EQ(monthly_base_temperature(2.0, 20.0, 12), 2.0);
  EXPECT_DOUBLE_EQ(monthly_base_temperature(2.0, 20.0, 6), 20.0);
  EXPECT_DOUBLE_EQ(monthly_base_temperature(2.0, 20.0, 1), 5.0);
  EXPECT_DOUBLE_EQ(monthly_base_temperature(2.0, 20.0, 3), 11.0);
  for (int k = 1; k <= 5; ++k)
    EXPECT_DOUBLE_EQ(monthly_base_temperature(2.0, 20.0, 6 - k), monthly_base_temperature(2.0, 20.0, 6 + k));

  Heightfield z(Domain::from_extent({0, 0}, {100, 100}, {3, 3}));
  z.at(0, 0) = 0.0f;
  z.at(1, 0) = 1000.0f;
  z.at(2, 0) = 2500.0f;
  z.at(0, 1) = 300.0f;
  TemperatureParams p;
  p.t_december = 2.0;
  p.t_june = 20.0;
  p.lapse_rate = 6.4;
  p.reference_altitude = 300.0;
  const auto r = temperature(z, p);
  for (int m = 1; m <= 12; ++m) {
    const double base = monthly_base_temperature(2.0, 20.0, m);
    EXPECT_NEAR(r.monthly->pixel(0, 1)[m - 1], base, 1e-5);
    EXPECT_NEAR(r.monthly->pixel(0, 0)[m - 1], base + 0.3 * 6.4, 1e-5);
    EXPECT_NEAR(r.monthly->pixel(1, 0)[m - 1], base - 0.7 * 6.4, 1e-5);
    EXPECT_NEAR(r.monthly->pixel(2, 0)[m - 1], base - 2.2 * 6.4, 1e-5);
  }
  double mean = 0.0;
  for (int m = 1; m <= 12; ++m) mean += monthly_base_temperature(2.0, 20.0, m) / 12.0;
  EXPECT_NEAR(r.mean->at(0, 1), mean, 1e-5);
  // Illumination term: +gain per lit hour above the reference.
  Image lit(z.domain, 1, 14.0f);
  p.illumination_gain = 0.5;
  const auto r2 = temperature(z, p, &lit);
  EXPECT_NEAR(r2.monthly->pixel(0, 1)[5] - r.monthly->pixel(0, 1)[5], 1.0, 1e-5);
}

TEST(SoilHumidity, NeverExceedsRainfallAndHistoryMatchesHand) {
  Heightfield z(Domain::from_extent({0, 0}, {300, 300}, {31, 31}));
  for (int j = 0; j < 31; ++j)
    for (int i = 0; i < 31; ++i)
      z.at(i, j) = static_cast<float>(i < 15 ? 0.0 : 2.0 * (i - 15) * 10.0);  // flat, then 63 deg
  auto p = SoilHumidityParams::defaults();
  p.intensity.points = {{1.0, 10.0}, {12.0, 10.0}};
  p.infiltration = 4.0;  // 40 % of the rain infiltrates
  Heightfield wet(z.domain, 0.0f);
  wet.at(5, 20) = 0.5f;
  Heightfield water(z.domain, 0.0f);
  water.at(6, 20) = 1.0f;
  const auto r = soil_humidity(z, p, nullptr, &wet, &water);
  double rain[12];
  for (int m = 1; m <= 12; ++m) rain[m - 1] = p.rainfall.evaluate(m);
  for (std::size_t c = 0; c < z.data.size(); ++c)
    for (int m = 0; m < 12; ++m) {
      EXPECT_LE(r.monthly->data[c * 12 + std::size_t(m)], rain[m] + 1e-4);
      EXPECT_GE(r.monthly->data[c * 12 + std::size_t(m)], 0.0f);
    }
  // Hand computation on flat dry ground: S = 0.4 R; S_wh(jan) = S(jan)/2 + S(dec)/3 + S(nov)/6.
  const float* mo = r.monthly->pixel(3, 3);
  const float* we = r.weighted->pixel(3, 3);
  EXPECT_NEAR(mo[0], 0.4 * 80.0, 1e-4);
  EXPECT_NEAR(we[0], 0.4 * (80.0 / 2 + 90.0 / 3 + 80.0 / 6), 1e-4);
  EXPECT_NEAR(we[1], 0.4 * (70.0 / 2 + 80.0 / 3 + 90.0 / 6), 1e-4);
  EXPECT_NEAR(we[6], 0.4 * (15.0 / 2 + 25.0 / 3 + 40.0 / 6), 1e-4);
  EXPECT_DOUBLE_EQ(kHumidityWeights[0] + kHumidityWeights[1] + kHumidityWeights[2], 1.0);
  // Cliffs absorb nothing; wetness 0.5 absorbs 0.4 + 0.5 * 0.6 = 0.7; standing water saturates.
  EXPECT_EQ(r.monthly->pixel(25, 3)[0], 0.0f);
  EXPECT_NEAR(r.monthly->pixel(5, 20)[0], 0.7 * 80.0, 1e-4);
  EXPECT_NEAR(r.monthly->pixel(6, 20)[0], 80.0, 1e-4);
  // The annual figure is the sum of the weighted months (= the sum of the months: the weights sum to 1).
  double sum = 0.0;
  for (int m = 0; m < 12; ++m) sum += mo[m];
  EXPECT_NEAR(r.annual->at(3, 3), sum, 1e-3);
}

TEST(ResourceStack, ChannelsAndKeys) {
  const Domain d = Domain::from_extent({0, 0}, {640, 640}, {17, 17});
  auto z = std::make_shared<Heightfield>(make_field(17, 40.0, hills));
  const auto t = run_node("Temperature", d, {}, {{"in", PortValue(HeightfieldPtr(z))}});
  const auto s = run_node("SoilHumidity", d, {}, {{"in", PortValue(HeightfieldPtr(z))}});
  const auto l = run_node("SunIllumination", d, {}, {{"in", PortValue(HeightfieldPtr(z))}});
  const auto r = run_node("ResourceStack", d, {},
                          {{"in", PortValue(HeightfieldPtr(z))},
                           {"temperature", t.outputs[0]},
                           {"illumination", l.outputs[0]},
                           {"humidity", s.outputs[0]}});
  const auto img = r.get<Image>(0);
  ASSERT_EQ(img->channels, 37);
  EXPECT_EQ(img->channel_names[0], "slope");
  EXPECT_EQ(img->channel_names[1], "temperature_jan");
  EXPECT_EQ(img->channel_names[13], "illumination_jan");
  EXPECT_EQ(img->channel_names[36], "humidity_dec");
  EXPECT_EQ(img->pixel(3, 4)[1 + 5], t.get<Image>(0)->pixel(3, 4)[5]);
  for (const char* type : {"Temperature", "SoilHumidity", "ResourceStack"}) {
    expect_every_param_changes_key(type, d);
    expect_every_input_changes_key(type, d);
  }
}

TEST(Biomes, WhittakerAndIslandTables) {
  const BiomeTable w = biome_table_from_rows(builtin_biome_rectangles("whittaker"));
  auto name = [&](const BiomeTable& t, double T, double M) {
    const int id = t.classify(T, M);
    return id < 0 ? std::string("none") : t.names[std::size_t(id)];
  };
  EXPECT_EQ(name(w, -10, 300), "tundra");
  EXPECT_EQ(name(w, 0, 800), "boreal_forest");
  EXPECT_EQ(name(w, 0, 100), "temperate_grassland_desert");
  EXPECT_EQ(name(w, 12, 1500), "temperate_seasonal_forest");
  EXPECT_EQ(name(w, 12, 3000), "temperate_rain_forest");
  EXPECT_EQ(name(w, 25, 200), "subtropical_desert");
  EXPECT_EQ(name(w, 25, 1500), "tropical_seasonal_forest_savanna");
  EXPECT_EQ(name(w, 27, 4000), "tropical_rain_forest");
  // The whittaker table covers the whole plane.
  for (double T = -40; T <= 40; T += 0.5)
    for (double M = 0; M <= 5000; M += 25) ASSERT_GE(w.classify(T, M), 0) << T << " " << M;
  const BiomeTable is = biome_table_from_rows(builtin_biome_rectangles("island"));
  EXPECT_EQ(name(is, -5, 0.9), "snow");
  EXPECT_EQ(name(is, -5, 0.05), "scorched");
  EXPECT_EQ(name(is, 20, 0.9), "tropical_rain_forest");
  EXPECT_EQ(name(is, 10, 0.05), "temperate_desert");
  EXPECT_EQ(is.classify(10, 0.05), is.classify(4, 0.1)) << "one name, one id";
}

TEST(Biomes, CustomTableAndErrors) {
  const TableSchema schema = biome_rectangle_schema();
  const BiomeTable t = biome_table_from_rows(table_from_json_text(
      R"([{"name": "cold", "temperature": [null, 0], "moisture": [null, null], "color": "#0000ff"},
          {"name": "warm", "temperature": [0, null], "moisture": [0, null], "color": "#ff0000"},
          {"name": "cold", "temperature": [0, null], "moisture": [-10, -5], "color": "#00ff00"}])",
      schema));
  EXPECT_EQ(t.names.size(), 2u);
  EXPECT_EQ(t.classify(-3, 5), 0);
  EXPECT_EQ(t.classify(3, 5), 1);
  EXPECT_EQ(t.classify(3, -7), 0) << "a name's second rectangle is the same biome";
  EXPECT_EQ(t.classify(3, -1), -1);
  EXPECT_NEAR(t.colors[1].r, 1.0f, 1e-6);
  EXPECT_EQ(t.colors[0], glm::vec4(0, 0, 1, 1)) << "a biome's color is its first row's";
  // Malformed tables name the row and column.
  auto error = [&](const char* text) {
    TableProblem problem;
    EXPECT_FALSE(table_from_json(nlohmann::json::parse(text), schema, problem).has_value()) << text;
    return problem.str("custom_table");
  };
  EXPECT_EQ(error(R"([{"name": "a", "temperature": [1, 2], "moisture": [3, 4]}])"),
            "custom_table[0].color: the column 'color' is required");
  EXPECT_EQ(error(R"([{"name": "a", "temperature": [1, "x"], "moisture": [3, 4], "color": "#ffffff"}])"),
            "custom_table[0].temperature: maximum: expected a number or null (open end), found the string \"x\"");
  EXPECT_EQ(error(R"([{"name": "a", "temperature": [1, 2], "moisture": [3, 4], "color": "red"}])"),
            "custom_table[0].color: 'red' is not a #rrggbb color");
  EXPECT_EQ(error(R"([{"name": "a", "temperature": [null, 2], "moisture": [4, 3], "color": "#ffffff"}])"),
            "custom_table[0].moisture: the range [4, 3] has min > max");
  EXPECT_EQ(error("[]"), "custom_table: at least 1 row(s) needed, found 0");
  const Domain d = Domain::from_extent({0, 0}, {640, 640}, {17, 17});
  auto temp = std::make_shared<Heightfield>(make_field(17, 40.0, hills));
  auto moist = std::make_shared<Heightfield>(d, 900.0f);
  const auto r = run_node("Biomes", d, {{"moisture_scale", 1.0}},
                          {{"in", PortValue(HeightfieldPtr(temp))}, {"moisture", PortValue(HeightfieldPtr(moist))}});
  EXPECT_EQ(r.get<Heightfield>(0)->data.size(), d.sample_count());
  expect_every_param_changes_key("Biomes", d);
  expect_every_input_changes_key("Biomes", d);
}

}  // namespace
}  // namespace orogen::climate
