// Shapes: RadialFalloff (island mask) and Cone.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "field_ops_fixtures.h"
#include "nodes/field/radial_falloff.h"

namespace orogen {
namespace {

using test::field_from;
using test::run_field;

TEST(RadialFalloff, OneAtTheCentreZeroBeyondTheRadiusAndMonotone) {
  const Domain d = Domain::from_extent({0, 0}, {4000, 4000}, {401, 401});  // 10 m, centre on a sample
  const auto m = run_field("RadialFalloff", d, {{"center", glm::dvec2(2000, 2000)}, {"radius", 1500.0}});
  EXPECT_EQ(m->at(200, 200), 1.0f);
  for (int j = 0; j < 401; ++j)
    for (int i = 0; i < 401; ++i) {
      const double r = std::hypot(d.x(i) - 2000, d.y(j) - 2000);
      const float v = m->at(i, j);
      ASSERT_GE(v, 0.0f);
      ASSERT_LE(v, 1.0f);
      if (r >= 1500.0) {
        ASSERT_EQ(v, 0.0f) << i << "," << j;
      }
      if (r < 1400.0) {
        ASSERT_GT(v, 0.0f) << i << "," << j;
      }
    }
  // Non-increasing along a ray from the centre.
  for (int i = 201; i < 401; ++i) EXPECT_LE(m->at(i, 200), m->at(i - 1, 200));
}

TEST(RadialFalloff, ProfileCurveAndDistanceOffset) {
  const Domain d = Domain::from_extent({-1000, -1000}, {2000, 2000}, {201, 201});
  const CurveValue linear{{{0.0, 1.0}, {1.0, 0.0}}};
  const auto m = run_field("RadialFalloff", d, {{"center", glm::dvec2(0, 0)}, {"radius", 800.0}, {"profile", linear}});
  EXPECT_NEAR(m->at(140, 100), 1.0 - 400.0 / 800.0, 1e-6);  // x = 400 m
  EXPECT_NEAR(m->at(100, 160), 1.0 - 600.0 / 800.0, 1e-6);  // y = 600 m
  // A constant offset of +200 m moves every contour 200 m inwards.
  const auto offset = field_from(d, [](double, double) { return 200.0; });
  const auto shifted =
      run_field("RadialFalloff", d, {{"center", glm::dvec2(0, 0)}, {"radius", 800.0}, {"profile", linear}},
                {{"distance_offset", offset}});
  EXPECT_NEAR(shifted->at(120, 100), m->at(140, 100), 1e-6);  // 200 m + 200 m == 400 m
}

TEST(Cone, ApexHeightLinearFlanksAndZeroBeyond) {
  const Domain d = Domain::from_extent({0, 0}, {1000, 1000}, {201, 201});  // 5 m
  const auto h = run_field("Cone", d, {{"center", glm::dvec2(500, 500)}, {"radius", 300.0}, {"height", 150.0}});
  EXPECT_EQ(h->at(100, 100), 150.0f);
  EXPECT_NEAR(h->at(130, 100), 150.0 * (1 - 150.0 / 300.0), 1e-4);
  EXPECT_EQ(h->at(170, 100), 0.0f);
  EXPECT_EQ(h->at(0, 0), 0.0f);
  // On the flanks, away from apex and rim, the slope is atan(height / radius).
  const auto s = run_field("Slope", d, {}, {{"in", h}});
  for (int i : {110, 120, 150}) EXPECT_NEAR(s->at(i, 100), std::atan(0.5) * 180 / std::numbers::pi, 1e-3);
}

}  // namespace
}  // namespace orogen
