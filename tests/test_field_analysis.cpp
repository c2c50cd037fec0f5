// Terrain analysis: Slope, Aspect, Curvature, Normals against analytic surfaces (planes, sphere caps,
// paraboloids) at several spacings.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "field_ops_fixtures.h"
#include "nodes/field/aspect.h"
#include "nodes/field/curvature.h"
#include "nodes/field/slope.h"

namespace orogen {
namespace {

using test::field_from;
using test::run_field;

constexpr double kDeg = 180.0 / std::numbers::pi;

TEST(Slope, PlaneZEqualsKxIsAtanKEverywhereForSeveralSpacings) {
  for (double spacing : {0.5, 2.0, 10.0}) {
    const Domain d = Domain::from_extent({0, 0}, {40 * spacing, 30 * spacing}, {41, 31});
    for (double k : {0.1, 0.5, 1.0, 3.0}) {
      const auto z = field_from(d, [=](double x, double) { return k * x; });
      const auto s = run_field("Slope", d, {}, {{"in", z}});
      const double expected = std::atan(k) * kDeg;
      for (int j = 0; j < d.height(); ++j)
        for (int i = 0; i < d.width(); ++i)
          ASSERT_NEAR(s->at(i, j), expected, 2e-3) << "k " << k << " spacing " << spacing << " at " << i << "," << j;
    }
  }
}

TEST(Slope, TiltedPlaneInAnyDirectionAndAnisotropicSpacing) {
  // 3 m by 7 m spacing: a gradient in samples would be wrong by those factors.
  const Domain d = Domain::from_extent({-60, 100}, {60 * 3.0, 20 * 7.0}, {61, 21});
  const double a = 0.3, b = -0.4;  // |grad| = 0.5
  const auto z = field_from(d, [=](double x, double y) { return a * x + b * y + 17.0; });
  const auto s = run_field("Slope", d, {}, {{"in", z}});
  for (float v : s->data) ASSERT_NEAR(v, std::atan(0.5) * kDeg, 2e-3);
}

TEST(Aspect, KnownPlanesFaceTheirDownhillCompassDirection) {
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {11, 11});
  struct Case {
    double a, b, expected;
  };  // z = a x + b y
  const Case cases[] = {
      {0, -1, 0},    // falls towards +y: faces north
      {-1, 0, 90},   // falls towards +x: east
      {0, 1, 180},   // falls towards -y: south
      {1, 0, 270},   // falls towards -x: west
      {-1, -1, 45},  // north-east
      {1, 1, 225},   // south-west
      {-std::sqrt(3.0), -1, 60},
  };
  for (const auto& c : cases) {
    const auto z = field_from(d, [&](double x, double y) { return c.a * x + c.b * y; });
    const auto asp = run_field("Aspect", d, {}, {{"in", z}});
    const auto north = run_field("Aspect", d, {{"output", std::string("northness")}}, {{"in", z}});
    const auto east = run_field("Aspect", d, {{"output", std::string("eastness")}}, {{"in", z}});
    for (int j = 0; j < 11; ++j)
      for (int i = 0; i < 11; ++i) {
        ASSERT_NEAR(asp->at(i, j), c.expected, 1e-3) << c.a << "," << c.b;
        ASSERT_NEAR(north->at(i, j), std::cos(c.expected / kDeg), 1e-5);
        ASSERT_NEAR(east->at(i, j), std::sin(c.expected / kDeg), 1e-5);
      }
  }
  const auto flat = field_from(d, [](double, double) { return 5.0; });
  EXPECT_EQ(run_field("Aspect", d, {{"flat_value", -1.0}}, {{"in", flat}})->at(4, 4), -1.0f);
  EXPECT_EQ(aspect_value(0, 0, AspectOutput::Northness, -1.0), 0.0);
}

// Sphere cap of radius R centred over the middle of the domain, heights relative to its top.
struct Cap {
  double R = 1000.0, cx = 400.0, cy = 400.0;
  double z(double x, double y) const { return std::sqrt(R * R - (x - cx) * (x - cx) - (y - cy) * (y - cy)) - R; }
  double rho(double x, double y) const { return std::hypot(x - cx, y - cy); }
};

TEST(Curvature, SphereCapMatchesAnalyticValues) {
  const Cap cap;
  for (int n : {201, 401}) {  // 4 m and 2 m spacing
    const Domain d = Domain::from_extent({0, 0}, {800, 800}, {n, n});
    const auto z = field_from(d, [&](double x, double y) { return cap.z(x, y); });
    const auto profile = run_field("Curvature", d, {{"type", std::string("profile")}}, {{"in", z}});
    const auto plan = run_field("Curvature", d, {{"type", std::string("plan")}}, {{"in", z}});
    const auto tangential = run_field("Curvature", d, {{"type", std::string("tangential")}}, {{"in", z}});
    const auto mean = run_field("Curvature", d, {{"type", std::string("mean")}}, {{"in", z}});
    int checked = 0;
    for (int j = 1; j < n - 1; j += 3)
      for (int i = 1; i < n - 1; i += 3) {
        const double rho = cap.rho(d.x(i), d.y(j));
        if (rho > 350.0) continue;
        EXPECT_NEAR(mean->at(i, j), 1.0 / cap.R, 0.01 / cap.R) << i << "," << j;
        if (rho < 40.0) continue;  // direction-based curvatures are ill-conditioned at the summit
        EXPECT_NEAR(profile->at(i, j), 1.0 / cap.R, 0.01 / cap.R) << i << "," << j;
        EXPECT_NEAR(tangential->at(i, j), 1.0 / cap.R, 0.01 / cap.R) << i << "," << j;
        EXPECT_NEAR(plan->at(i, j), 1.0 / rho, 0.01 / rho) << i << "," << j;
        ++checked;
      }
    EXPECT_GT(checked, 1000);
  }
}

TEST(Curvature, ParaboloidBowlIsConcaveWithKnownValues) {
  // z = rho^2 / (2a): a bowl; at the bottom both principal curvatures are 1/a (concave: negative).
  const double a = 500.0;
  const Domain d = Domain::from_extent({-200, -200}, {400, 400}, {201, 201});
  const auto z = field_from(d, [&](double x, double y) { return (x * x + y * y) / (2 * a); });
  const auto mean = run_field("Curvature", d, {{"type", std::string("mean")}}, {{"in", z}});
  const auto profile = run_field("Curvature", d, {{"type", std::string("profile")}}, {{"in", z}});
  const auto plan = run_field("Curvature", d, {{"type", std::string("plan")}}, {{"in", z}});
  EXPECT_NEAR(mean->at(100, 100), -1.0 / a, 1e-6);
  // Along the slope line the parabola y = r^2/2a has curvature (1/a) / (1 + (r/a)^2)^1.5; contours are
  // circles of radius r, curving towards the bowl's axis (concave).
  for (int i : {130, 150, 180}) {
    const double r = d.x(i), g = r / a;
    EXPECT_NEAR(profile->at(i, 100), -(1.0 / a) / std::pow(1 + g * g, 1.5), 1e-6);
    EXPECT_NEAR(plan->at(i, 100), -1.0 / r, 1e-3 / r);
  }
  // A plane has zero curvature of every kind.
  const auto plane = field_from(d, [](double x, double y) { return 0.2 * x - 0.1 * y; });
  for (const char* kind : {"profile", "plan", "tangential", "mean"}) {
    const auto c = run_field("Curvature", d, {{"type", std::string(kind)}}, {{"in", plane}});
    for (float v : c->data) ASSERT_NEAR(v, 0.0, 2e-5) << kind;  // float rounding of heights only
  }
}

TEST(Normals, PlaneGivesItsUnitNormalEverywhere) {
  const Domain d = Domain::from_extent({0, 0}, {90, 50}, {31, 11});  // 3 m x 5 m spacing
  const double a = 0.6, b = -0.25;
  const auto z = field_from(d, [=](double x, double y) { return a * x + b * y; });
  const auto img = run_node("Normals", d, {}, {{"in", z}}).get<Image>();
  ASSERT_EQ(img->channels, 3);
  const double len = std::sqrt(a * a + b * b + 1);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) {
      const float* n = img->pixel(i, j);
      ASSERT_NEAR(n[0], -a / len, 1e-5);
      ASSERT_NEAR(n[1], -b / len, 1e-5);
      ASSERT_NEAR(n[2], 1 / len, 1e-5);
      ASSERT_NEAR(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 1.0, 1e-5);
    }
  const auto enc = run_node("Normals", d, {{"encoding", std::string("unsigned")}}, {{"in", z}}).get<Image>();
  EXPECT_NEAR(enc->pixel(3, 3)[0], -a / len * 0.5 + 0.5, 1e-6);
  EXPECT_NEAR(enc->pixel(3, 3)[2], 1 / len * 0.5 + 0.5, 1e-6);
}

}  // namespace
}  // namespace orogen
