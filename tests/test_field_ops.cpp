// Point-wise field operators: Subtract, Min, Max, Blend, Remap, Clamp, Normalize, Curve, Power, Terrace,
// Invert, Abs, SmoothStep, Threshold, BandMask, ColorRamp. Known values, exact bounds, monotonicity and
// symmetry that would fail if the formulas were wrong.
#include <algorithm>
#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "field_ops_fixtures.h"
#include "graph/exec_context.h"
#include "graph/graph.h"
#include "nodes/field/band_mask.h"
#include "nodes/field/blend.h"
#include "nodes/field/color_ramp.h"
#include "nodes/field/curve_remap.h"
#include "nodes/field/power.h"
#include "nodes/field/remap.h"
#include "nodes/field/smoothstep.h"
#include "nodes/field/terrace.h"

namespace orogen {
namespace {

using test::field_from;
using test::run_field;

const Domain kLine = Domain::from_extent({0, 0}, {1000, 10}, {1001, 2});  // x = 0..1000 m in 1 m steps

HeightfieldPtr constant(const Domain& d, double v) {
  return field_from(d, [=](double, double) { return v; });
}

TEST(BinaryOps, KnownValues) {
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {11, 11});
  const auto a = field_from(d, [](double x, double) { return x; });
  const auto b = field_from(d, [](double, double y) { return y; });
  const auto sub = run_field("Subtract", d, {}, {{"a", a}, {"b", b}});
  const auto mn = run_field("Min", d, {}, {{"a", a}, {"b", b}});
  const auto mx = run_field("Max", d, {}, {{"a", a}, {"b", b}});
  for (int j = 0; j < 11; ++j)
    for (int i = 0; i < 11; ++i) {
      EXPECT_EQ(sub->at(i, j), static_cast<float>(10 * i - 10 * j));
      EXPECT_EQ(mn->at(i, j), static_cast<float>(10 * std::min(i, j)));
      EXPECT_EQ(mx->at(i, j), static_cast<float>(10 * std::max(i, j)));
    }
}

TEST(BinaryOps, SecondInputIsResampledOntoTheFirstDomain) {
  const Domain fine = Domain::from_extent({0, 0}, {100, 100}, {21, 21});  // 5 m
  const Domain coarse = Domain::from_extent({0, 0}, {100, 100}, {5, 5});  // 25 m
  const auto a = field_from(fine, [](double x, double y) { return x + y; });
  const auto b = field_from(coarse, [](double x, double y) { return 2 * x - y; });  // linear: bilinear is exact
  const auto out = run_field("Subtract", coarse, {}, {{"a", a}, {"b", b}});
  ASSERT_EQ(out->domain, fine);
  for (int j = 0; j < 21; ++j)
    for (int i = 0; i < 21; ++i) EXPECT_NEAR(out->at(i, j), (5.0 * i + 5.0 * j) - (10.0 * i - 5.0 * j), 1e-4);
}

TEST(Blend, ModesKnownValues) {
  EXPECT_DOUBLE_EQ(blend_value(BlendMode::Lerp, 0.2, 0.6, 0.5), 0.4);
  EXPECT_DOUBLE_EQ(blend_value(BlendMode::Lerp, 0.2, 0.6, 1.0), 0.6);
  EXPECT_DOUBLE_EQ(blend_value(BlendMode::Add, 0.2, 0.6, 1.0), 0.8);
  EXPECT_DOUBLE_EQ(blend_value(BlendMode::Add, 0.2, 0.6, 0.5), 0.5);
  EXPECT_NEAR(blend_value(BlendMode::Screen, 0.2, 0.6, 1.0), 0.68, 1e-15);
  EXPECT_NEAR(blend_value(BlendMode::Screen, 0.5, 0.5, 1.0), 0.75, 1e-15);
  EXPECT_DOUBLE_EQ(blend_value(BlendMode::Max, 0.2, 0.6, 1.0), 0.6);
  EXPECT_DOUBLE_EQ(blend_value(BlendMode::Max, 0.7, 0.6, 1.0), 0.7);
  for (auto m : {BlendMode::Lerp, BlendMode::Add, BlendMode::Screen, BlendMode::Max})
    EXPECT_DOUBLE_EQ(blend_value(m, 0.3, 0.9, 0.0), 0.3);
}

TEST(Blend, NodeUsesMaskAndFactor) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {11, 11});
  const auto a = constant(d, 100.0), b = constant(d, 300.0);
  const auto mask = field_from(d, [](double x, double) { return x / 10.0; });  // 0..1 along x
  const auto out =
      run_field("Blend", d, {{"mode", std::string("lerp")}, {"factor", 0.5}}, {{"a", a}, {"b", b}, {"mask", mask}});
  for (int i = 0; i <= 10; ++i) EXPECT_NEAR(out->at(i, 4), 100.0 + 200.0 * 0.5 * i / 10.0, 1e-4);
  const auto add = run_field("Blend", d, {{"mode", std::string("add")}}, {{"a", a}, {"b", b}});
  EXPECT_EQ(add->at(3, 3), 400.0f);
  const auto mx = run_field("Blend", d, {{"mode", std::string("max")}, {"factor", 1.0}}, {{"a", b}, {"b", a}});
  EXPECT_EQ(mx->at(3, 3), 300.0f);
}

TEST(Remap, HitsExactBoundsAndIsLinear) {
  const auto in = field_from(kLine, [](double x, double) { return x * 0.37 - 50.0; });  // -50 .. 320
  const double lo = -50.0, hi = 0.37 * 1000 - 50.0;
  const auto out =
      run_field("Remap", kLine, {{"in_min", lo}, {"in_max", hi}, {"out_min", 3.5}, {"out_max", 1234.25}}, {{"in", in}});
  EXPECT_EQ(out->at(0, 0), 3.5f);
  EXPECT_EQ(out->at(1000, 0), 1234.25f);
  EXPECT_NEAR(out->at(500, 0), (3.5 + 1234.25) / 2, 1e-3);
  // Reversed output range inverts; clamp keeps values inside the output range.
  const RemapRange rev{0.0, 10.0, 1.0, 0.0, true};
  EXPECT_DOUBLE_EQ(remap_value(0.0, rev), 1.0);
  EXPECT_DOUBLE_EQ(remap_value(10.0, rev), 0.0);
  EXPECT_DOUBLE_EQ(remap_value(25.0, rev), 0.0);
  EXPECT_DOUBLE_EQ(remap_value(-5.0, rev), 1.0);
  EXPECT_DOUBLE_EQ(remap_value(15.0, {0.0, 10.0, 0.0, 100.0, false}), 150.0);
}

TEST(Remap, EmptyInputRangeIsAnError) {
  EXPECT_THROW(run_field("Remap", kLine, {{"in_min", 2.0}, {"in_max", 2.0}}, {{"in", constant(kLine, 1)}}), NodeError);
}

TEST(Clamp, BoundsAndError) {
  const auto in = field_from(kLine, [](double x, double) { return x - 500.0; });
  const auto out = run_field("Clamp", kLine, {{"min", -100.0}, {"max", 250.0}}, {{"in", in}});
  EXPECT_EQ(out->at(0, 0), -100.0f);
  EXPECT_EQ(out->at(450, 0), -50.0f);
  EXPECT_EQ(out->at(1000, 0), 250.0f);
  EXPECT_THROW(run_field("Clamp", kLine, {{"min", 1.0}, {"max", 0.0}}, {{"in", in}}), NodeError);
}

TEST(Normalize, HitsExactBounds) {
  const Domain d = Domain::from_extent({0, 0}, {2000, 2000}, {97, 83});
  const auto in = field_from(d, test::rolling_hills);
  const auto out = run_field("Normalize", d, {{"min", -20.0}, {"max", 750.0}}, {{"in", in}});
  const auto [lo, hi] = std::minmax_element(out->data.begin(), out->data.end());
  EXPECT_EQ(*lo, -20.0f);
  EXPECT_EQ(*hi, 750.0f);
  // Order is preserved: the argmin and argmax of the input are those of the output.
  const auto [ilo, ihi] = std::minmax_element(in->data.begin(), in->data.end());
  EXPECT_EQ(ilo - in->data.begin(), lo - out->data.begin());
  EXPECT_EQ(ihi - in->data.begin(), hi - out->data.begin());
  // A flat field becomes the low bound.
  const auto flat = run_field("Normalize", d, {{"min", 5.0}, {"max", 9.0}}, {{"in", constant(d, 3.0)}});
  for (float v : flat->data) EXPECT_EQ(v, 5.0f);
}

TEST(Curve, IdentityPointsGiveTheIdentity) {
  const auto in = field_from(kLine, [](double x, double) { return 0.25 * x; });  // 0..250 m
  const CurveValue identity{{{0.0, 0.0}, {0.3, 0.3}, {0.8, 0.8}, {1.0, 1.0}}};
  const auto out =
      run_field("Curve", kLine, {{"curve", identity}, {"input_min", 0.0}, {"input_max", 250.0}}, {{"in", in}});
  for (int i = 0; i <= 1000; ++i) EXPECT_NEAR(out->at(i, 0), in->at(i, 0), 1e-4) << i;
  const auto field_range =
      run_field("Curve", kLine, {{"curve", CurveValue::identity()}, {"range", std::string("field")}}, {{"in", in}});
  for (int i = 0; i <= 1000; ++i) EXPECT_NEAR(field_range->at(i, 0), in->at(i, 0), 1e-4) << i;
}

TEST(Curve, MonotonePointsGiveMonotoneOutput) {
  const auto in = field_from(kLine, [](double x, double) { return x - 100.0; });  // -100..900 m
  const CurveValue steps{{{0.0, 0.0}, {0.2, 0.6}, {0.25, 0.62}, {0.5, 0.65}, {0.55, 0.9}, {1.0, 1.0}}};
  const auto out =
      run_field("Curve", kLine, {{"curve", steps}, {"input_min", 0.0}, {"input_max", 800.0}}, {{"in", in}});
  for (int i = 1; i <= 1000; ++i) EXPECT_GE(out->at(i, 0), out->at(i - 1, 0)) << i;
  // The range maps onto itself, values outside clamp, and control points are hit.
  EXPECT_EQ(out->at(0, 0), 0.0f);       // -100 m clamps to curve(0) = 0
  EXPECT_EQ(out->at(1000, 0), 800.0f);  // 900 m clamps to 800
  EXPECT_NEAR(curve_remap_value(0.2 * 800, steps, 0, 800), 0.6 * 800, 1e-9);
  EXPECT_NEAR(curve_remap_value(0.55 * 800, steps, 0, 800), 0.9 * 800, 1e-9);
}

TEST(Power, OddSymmetricAboutThePivotWithFixedPoints) {
  const PowerParams p{1.5, 0.0, 1.0};
  EXPECT_DOUBLE_EQ(power_value(0.25, p), 0.125);  // Weiss 2015 Eq 3: 0.25^1.5
  EXPECT_DOUBLE_EQ(power_value(-0.25, p), -0.125);
  const PowerParams q{2.3, 120.0, 80.0};
  for (double d : {0.0, 3.0, 40.0, 80.0, 200.0}) {
    EXPECT_NEAR(power_value(q.pivot + d, q) - q.pivot, -(power_value(q.pivot - d, q) - q.pivot), 1e-9) << d;
  }
  EXPECT_NEAR(power_value(200.0, q), 200.0, 1e-9);  // pivot + scale is fixed
  EXPECT_NEAR(power_value(40.0, q), 40.0, 1e-9);    // pivot - scale is fixed
  // The node on a field symmetric about the pivot.
  const auto in = field_from(kLine, [](double x, double) { return (x - 500.0) / 250.0; });  // -2..2
  const auto out = run_field("Power", kLine, {{"exponent", 3.0}}, {{"in", in}});
  for (int i = 0; i <= 1000; ++i) EXPECT_EQ(out->at(i, 0), -out->at(1000 - i, 0)) << i;
  EXPECT_NEAR(out->at(1000, 0), 8.0f, 1e-5);
}

TEST(Terrace, HardStepsHaveTheLevelCount) {
  const auto in = field_from(kLine, [](double x, double) { return 0.12 * x - 10.0; });  // -10..110 m
  const auto out = run_field("Terrace", kLine,
                             {{"mode", std::string("count")},
                              {"levels", std::int64_t{7}},
                              {"range_min", 0.0},
                              {"range_max", 100.0},
                              {"sharpness", 1.0}},
                             {{"in", in}});
  std::set<float> levels;
  for (int i = 0; i <= 1000; ++i) {
    const float h = in->at(i, 0);
    if (h > 0.0f && h < 100.0f)
      levels.insert(out->at(i, 0));
    else
      EXPECT_EQ(out->at(i, 0), h);  // identity outside the range
  }
  EXPECT_EQ(levels.size(), 7u);
  for (float v : levels) EXPECT_NEAR(std::remainder(v, 100.0 / 7.0), 0.0, 1e-4);  // on a level
}

TEST(Terrace, MonotoneAndLevelsAreFixedPoints) {
  for (double s : {0.0, 0.3, 0.7, 0.95}) {
    const TerraceParams p{5.0, 12.5, s};
    double prev = -1e300;
    for (int k = -400; k <= 400; ++k) {
      const double h = k * 0.37;
      const double v = terrace_value(h, p);
      EXPECT_GE(v, prev) << "sharpness " << s << " at " << h;
      prev = v;
    }
    for (int level = -3; level <= 3; ++level)
      EXPECT_NEAR(terrace_value(5.0 + 12.5 * level, p), 5.0 + 12.5 * level, 1e-9);
  }
  EXPECT_NEAR(terrace_value(7.0, {0.0, 10.0, 0.0}), 7.0, 1e-12);  // sharpness 0 is the identity
  const auto in = field_from(kLine, [](double x, double) { return x * 0.3; });
  const auto out =
      run_field("Terrace", kLine, {{"mode", std::string("spacing")}, {"spacing", 20.0}, {"offset", 3.0}}, {{"in", in}});
  for (int i = 1; i <= 1000; ++i) EXPECT_GE(out->at(i, 0), out->at(i - 1, 0));
}

TEST(InvertAbs, KnownValues) {
  const auto in = field_from(kLine, [](double x, double) { return x - 300.0; });
  const auto inv = run_field("Invert", kLine, {}, {{"in", in}});
  const auto inv_mask = run_field("Invert", kLine, {{"pivot", 0.5}}, {{"in", constant(kLine, 0.25)}});
  const auto ab = run_field("Abs", kLine, {}, {{"in", in}});
  for (int i = 0; i <= 1000; ++i) {
    EXPECT_EQ(inv->at(i, 0), -in->at(i, 0));
    EXPECT_EQ(ab->at(i, 0), std::abs(in->at(i, 0)));
  }
  EXPECT_EQ(inv_mask->at(5, 1), 0.75f);
}

TEST(SmoothStep, EdgesMidpointAndMonotone) {
  EXPECT_EQ(smoothstep_value(-1.0, 0.0, 10.0), 0.0);
  EXPECT_EQ(smoothstep_value(0.0, 0.0, 10.0), 0.0);
  EXPECT_EQ(smoothstep_value(5.0, 0.0, 10.0), 0.5);
  EXPECT_EQ(smoothstep_value(10.0, 0.0, 10.0), 1.0);
  EXPECT_NEAR(smoothstep_value(2.5, 0.0, 10.0), 0.15625, 1e-15);
  EXPECT_EQ(smoothstep_value(12.0, 10.0, 0.0), 0.0);  // reversed edges fall
  const auto in = field_from(kLine, [](double x, double) { return x; });
  const auto out = run_field("SmoothStep", kLine, {{"edge0", 200.0}, {"edge1", 600.0}}, {{"in", in}});
  EXPECT_EQ(out->at(200, 0), 0.0f);
  EXPECT_EQ(out->at(400, 0), 0.5f);
  EXPECT_EQ(out->at(600, 0), 1.0f);
  for (int i = 1; i <= 1000; ++i) EXPECT_GE(out->at(i, 0), out->at(i - 1, 0));
  const auto th = run_field("Threshold", kLine, {{"level", 250.0}}, {{"in", in}});
  const auto thi = run_field("Threshold", kLine, {{"level", 250.0}, {"invert", true}}, {{"in", in}});
  EXPECT_EQ(th->at(249, 0), 0.0f);
  EXPECT_EQ(th->at(250, 0), 1.0f);
  EXPECT_EQ(thi->at(249, 0), 1.0f);
  EXPECT_EQ(thi->at(250, 0), 0.0f);
}

TEST(BandMask, OneInsideZeroFarOutsideSmoothBetween) {
  const auto in = field_from(kLine, [](double x, double) { return x; });
  const auto out = run_field("BandMask", kLine, {{"min", 300.0}, {"max", 500.0}, {"falloff", 100.0}}, {{"in", in}});
  for (int i = 300; i <= 500; ++i) EXPECT_EQ(out->at(i, 0), 1.0f);
  for (int i = 0; i <= 200; ++i) EXPECT_EQ(out->at(i, 0), 0.0f);
  for (int i = 600; i <= 1000; ++i) EXPECT_EQ(out->at(i, 0), 0.0f);
  EXPECT_NEAR(out->at(250, 0), 0.5f, 1e-6);
  for (int i = 201; i <= 300; ++i) EXPECT_GE(out->at(i, 0), out->at(i - 1, 0));
  for (int i = 501; i <= 600; ++i) EXPECT_LE(out->at(i, 0), out->at(i - 1, 0));
  // Sharpness (SeamScape Table 1): width = (max - min) / sharpness = 100 m for sharpness 2 on a 200 m band.
  const auto sharp = run_field("BandMask", kLine, {{"min", 300.0}, {"max", 500.0}, {"sharpness", 2.0}}, {{"in", in}});
  EXPECT_TRUE(test::bit_identical(sharp->data, out->data));
  EXPECT_EQ(band_mask_value(299.0, {300.0, 500.0, 0.0}), 0.0);  // no falloff: hard edges
}

TEST(ColorRamp, EndpointsEqualTheGradientEnds) {
  const auto in = field_from(kLine, [](double x, double) { return x; });
  GradientValue g{{{0.0, {1.0f, 0.0f, 0.0f, 1.0f}}, {0.4, {0.0f, 1.0f, 0.0f, 1.0f}}, {1.0, {0.1f, 0.2f, 0.9f, 0.5f}}}};
  const auto img =
      run_node("ColorRamp", kLine, {{"gradient", g}, {"input_min", 100.0}, {"input_max", 900.0}}, {{"in", in}})
          .get<Image>();
  ASSERT_EQ(img->channels, 4);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(img->pixel(100, 0)[k], g.stops.front().color[k]);
    EXPECT_EQ(img->pixel(0, 0)[k], g.stops.front().color[k]);  // below the range: first colour
    EXPECT_EQ(img->pixel(900, 0)[k], g.stops.back().color[k]);
    EXPECT_EQ(img->pixel(1000, 0)[k], g.stops.back().color[k]);
    EXPECT_NEAR(img->pixel(420, 0)[k], g.stops[1].color[k], 1e-6);  // t = 0.4
  }
  // The default ramp has water below 0 m and land colours above, with a hard shoreline.
  const GradientValue def = terrain_height_gradient();
  const auto at = [&](double h) {
    return def.evaluate((h - kTerrainGradientMin) / (kTerrainGradientMax - kTerrainGradientMin));
  };
  EXPECT_GT(at(-50.0).b, at(-50.0).r);  // water is blue
  EXPECT_GT(at(-0.01).b, at(-0.01).r);
  EXPECT_GT(at(0.5).r, at(0.5).b);      // sand
  EXPECT_GT(at(100.0).g, at(100.0).r);  // grass
  EXPECT_GT(at(880.0).r, 0.8f);         // snow
  EXPECT_GT(at(880.0).b, 0.8f);
}

}  // namespace
}  // namespace orogen
