// Constant, LinearGradient, Add, Multiply: known values at known world points, resolution independence and
// resampling of mismatched domains.
#include <cmath>
#include <memory>
#include <numbers>

#include <glm/geometric.hpp>

#include <gtest/gtest.h>

#include "evaluator/run_node.h"
#include "graph/exec_context.h"
#include "graph/graph.h"
#include "nodes/common/resample.h"
#include "nodes/field/add.h"
#include "nodes/field/linear_gradient.h"
#include "nodes/field/multiply.h"

namespace orogen {
namespace {

HeightfieldPtr make_field(const Domain& d, double (*f)(double x, double y)) {
  auto h = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) h->at(i, j) = static_cast<float>(f(d.x(i), d.y(j)));
  return h;
}

TEST(Constant, EverySampleHasTheValue) {
  const Domain d = Domain::from_extent({-50, 20}, {100, 300}, {17, 33});
  const auto run = run_node("Constant", d, {{"value", 12.5}});
  const auto h = run.get<Heightfield>();
  ASSERT_EQ(h->domain, d);
  for (float v : h->data) EXPECT_EQ(v, 12.5f);
}

TEST(LinearGradient, KnownValuesAlongX) {
  // 0 m at x = 100, 50 m at x = 600, clamped outside.
  const Domain d = Domain::from_extent({0, 0}, {1000, 1000}, {11, 11});  // samples every 100 m
  const auto run =
      run_node("LinearGradient", d,
               {{"from", 0.0}, {"to", 50.0}, {"angle", 0.0}, {"start", glm::dvec2(100, 0)}, {"length", 500.0}});
  const auto h = run.get<Heightfield>();
  for (int j = 0; j < 11; ++j) {
    EXPECT_FLOAT_EQ(h->at(0, j), 0.0f);    // x = 0, before the span
    EXPECT_FLOAT_EQ(h->at(1, j), 0.0f);    // x = 100, start
    EXPECT_FLOAT_EQ(h->at(2, j), 10.0f);   // x = 200
    EXPECT_FLOAT_EQ(h->at(6, j), 50.0f);   // x = 600, end
    EXPECT_FLOAT_EQ(h->at(10, j), 50.0f);  // x = 1000, after the span
    EXPECT_NEAR(h->at(4, j), 30.0f, 1e-4);
  }
}

TEST(LinearGradient, DirectionAngleAndStartPoint) {
  LinearGradientParams p;
  p.from = 10;
  p.to = -10;
  p.angle_deg = 90;  // increasing t towards +y
  p.start = {5, 5};
  p.length = 20;
  EXPECT_NEAR(linear_gradient_at(p, {5, 5}), 10.0, 1e-12);
  EXPECT_NEAR(linear_gradient_at(p, {1000, 15}), 0.0, 1e-9);  // x does not matter
  EXPECT_NEAR(linear_gradient_at(p, {-3, 25}), -10.0, 1e-9);
  EXPECT_NEAR(linear_gradient_at(p, {0, -100}), 10.0, 1e-12);
  // 45 degrees: the value depends on (x + y) / sqrt(2) only.
  p = {};
  p.from = 0;
  p.to = 1;
  p.angle_deg = 45;
  p.length = std::sqrt(2.0) * 100;
  EXPECT_NEAR(linear_gradient_at(p, {50, 50}), 0.5, 1e-12);
  EXPECT_NEAR(linear_gradient_at(p, {100, 0}), 0.5, 1e-12);
  EXPECT_NEAR(linear_gradient_at(p, {0, 100}), 0.5, 1e-12);
  EXPECT_NEAR(linear_gradient_at(p, {100, 100}), 1.0, 1e-12);
  // 180 degrees: increasing towards -x.
  p = {};
  p.angle_deg = 180;
  p.from = 0;
  p.to = 100;
  p.length = 100;
  EXPECT_NEAR(linear_gradient_at(p, {-25, 7}), 25.0, 1e-9);
  EXPECT_NEAR(linear_gradient_at(p, {25, 7}), 0.0, 1e-9);
}

TEST(LinearGradient, ResolutionIndependent) {
  // 64^2 and 257^2 samples of the same rectangle: every coarse sample equals the node evaluated at that
  // single world point, the shared lattice points (63 and 256 intervals share only the corners) are equal,
  // and the fine field interpolated at the coarse points agrees where the ramp is linear.
  const std::map<std::string, ParamValue> params{
      {"from", -20.0}, {"to", 80.0}, {"angle", 30.0}, {"start", glm::dvec2(100, 200)}, {"length", 700.0}};
  const Domain coarse = Domain::from_extent({0, 0}, {1260, 1260}, {64, 64});  // spacing 20 m
  const Domain fine = Domain::from_extent({0, 0}, {1260, 1260}, {257, 257});  // spacing 4.921875 m
  const auto hc = run_node("LinearGradient", coarse, params).get<Heightfield>();
  const auto hf = run_node("LinearGradient", fine, params).get<Heightfield>();
  for (int j = 0; j < 64; j += 9)
    for (int i = 0; i < 64; i += 7) {
      const Domain point = Domain::from_extent(coarse.position(i, j), {0, 0}, {1, 1});
      EXPECT_EQ(run_node("LinearGradient", point, params).get<Heightfield>()->at(0, 0), hc->at(i, j)) << i << "," << j;
    }
  EXPECT_EQ(hc->at(0, 0), hf->at(0, 0));
  EXPECT_EQ(hc->at(63, 0), hf->at(256, 0));
  EXPECT_EQ(hc->at(0, 63), hf->at(0, 256));
  EXPECT_EQ(hc->at(63, 63), hf->at(256, 256));
  const double a = 30.0 * std::numbers::pi / 180.0;
  const glm::dvec2 dir{std::cos(a), std::sin(a)};
  const double near_kink = fine.spacing.x * std::sqrt(2.0);
  int linear_points = 0;
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) {
      const auto p = coarse.position(i, j);
      const double s = glm::dot(p - glm::dvec2(100, 200), dir);  // distance along the ramp
      const bool linear_cell = s > near_kink && s < 700.0 - near_kink;
      const bool flat_cell = s < -near_kink || s > 700.0 + near_kink;
      // Bilinear interpolation reproduces a linear or constant function; near a clamp kink it may differ by
      // at most the slope times a fine cell diagonal.
      const double tol = (linear_cell || flat_cell) ? 2e-4 : 100.0 / 700.0 * near_kink;
      linear_points += linear_cell;
      EXPECT_NEAR(hf->sample_world(p.x, p.y), hc->at(i, j), tol) << i << "," << j;
    }
  EXPECT_GT(linear_points, 500);
}

TEST(LinearGradient, SharedLatticePointsBitIdentical) {
  // A 65^2 and a 257^2 grid over the same rectangle share every 4th fine sample exactly.
  const std::map<std::string, ParamValue> params{
      {"from", 3.0}, {"to", -40.0}, {"angle", -70.0}, {"start", glm::dvec2(-300, 50)}, {"length", 900.0}};
  const Domain coarse = Domain::from_extent({-512, -512}, {1024, 1024}, {65, 65});
  const Domain fine = Domain::from_extent({-512, -512}, {1024, 1024}, {257, 257});
  const auto hc = run_node("LinearGradient", coarse, params).get<Heightfield>();
  const auto hf = run_node("LinearGradient", fine, params).get<Heightfield>();
  for (int j = 0; j < 65; ++j)
    for (int i = 0; i < 65; ++i) ASSERT_EQ(hc->at(i, j), hf->at(4 * i, 4 * j)) << i << "," << j;
}

TEST(LinearGradient, TileMatchesWholeDomain) {
  const Domain whole = Domain::from_extent({0, 0}, {1000, 1000}, {101, 101});
  const Domain tile = whole.subdomain(40, 60, 31, 21);
  const auto hw = run_node("LinearGradient", whole, {{"angle", 120.0}, {"length", 800.0}}).get<Heightfield>();
  const auto ht = run_node("LinearGradient", tile, {{"angle", 120.0}, {"length", 800.0}}).get<Heightfield>();
  for (int j = 0; j < 21; ++j)
    for (int i = 0; i < 31; ++i) ASSERT_EQ(ht->at(i, j), hw->at(40 + i, 60 + j));
}

TEST(Add, KnownValuesWithWeights) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {11, 11});
  const auto a = make_field(d, [](double x, double y) { return x + 2 * y; });
  const auto b = make_field(d, [](double x, double y) { return x * y; });
  const auto out = run_node("Add", d, {{"weight_a", 2.0}, {"weight_b", -0.5}}, {{"a", a}, {"b", b}}).get<Heightfield>();
  for (int j = 0; j < 11; ++j)
    for (int i = 0; i < 11; ++i) EXPECT_FLOAT_EQ(out->at(i, j), 2.0f * (i + 2 * j) - 0.5f * (i * j));
  const auto plain = run_node("Add", d, {}, {{"a", a}, {"b", b}}).get<Heightfield>();
  for (int j = 0; j < 11; ++j)
    for (int i = 0; i < 11; ++i) EXPECT_FLOAT_EQ(plain->at(i, j), static_cast<float>(i + 2 * j + i * j));
}

TEST(Add, MissingInputIsAnError) {
  const Domain d = Domain::from_extent({0, 0}, {10, 10}, {4, 4});
  const auto a = make_field(d, [](double, double) { return 1.0; });
  EXPECT_THROW(run_node("Add", d, {}, {{"a", a}}), NodeError);
}

TEST(Multiply, KnownValuesWithScale) {
  const Domain d = Domain::from_extent({-5, -5}, {10, 10}, {6, 6});
  const auto a = make_field(d, [](double x, double) { return x; });
  const auto b = make_field(d, [](double, double y) { return y; });
  const auto out = run_node("Multiply", d, {{"scale", 3.0}}, {{"a", a}, {"b", b}}).get<Heightfield>();
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) EXPECT_FLOAT_EQ(out->at(i, j), static_cast<float>(3.0 * d.x(i) * d.y(j)));
}

TEST(Add, ResamplesMismatchedDomainBilinearly) {
  // b is a plane on a coarser, larger lattice: bilinear resampling reproduces a plane exactly (up to float),
  // and values beyond b's rectangle repeat its border.
  const Domain da = Domain::from_extent({0, 0}, {100, 100}, {41, 41});
  const Domain db = Domain::from_extent({-10, -10}, {90, 120}, {7, 9});  // x in [-10, 80], y in [-10, 110]
  const auto a = make_field(da, [](double, double) { return 0.0; });
  const auto b = make_field(db, [](double x, double y) { return 0.5 * x - 0.25 * y + 3; });
  const auto out = run_node("Add", da, {}, {{"a", a}, {"b", b}}).get<Heightfield>();
  ASSERT_EQ(out->domain, da);
  for (int j = 0; j < 41; ++j)
    for (int i = 0; i < 41; ++i) {
      const double x = std::min(da.x(i), 80.0), y = da.y(j);
      EXPECT_NEAR(out->at(i, j), 0.5 * x - 0.25 * y + 3, 1e-4) << i << "," << j;
    }
  // Where b's lattice coincides with a's samples the value is copied exactly (no blending from round-off):
  // b sample (2, 2) is at (20, 20) = a sample (8, 8).
  EXPECT_EQ(out->at(8, 8), b->at(2, 2));
}

TEST(Multiply, ResamplesMismatchedDomainBilinearly) {
  const Domain da = Domain::from_extent({0, 0}, {64, 64}, {33, 33});
  const Domain db = Domain::from_extent({0, 0}, {64, 64}, {5, 5});  // every 16 m
  const auto a = make_field(da, [](double, double) { return 2.0; });
  // b: 1 at the sample (2, 2) (world 32, 32), 0 elsewhere; bilinear gives a tent of radius 16 m.
  auto b = std::make_shared<Heightfield>(db, 0.0f);
  b->at(2, 2) = 1.0f;
  const auto out = run_node("Multiply", da, {}, {{"a", a}, {"b", HeightfieldPtr(b)}}).get<Heightfield>();
  for (int j = 0; j < 33; ++j)
    for (int i = 0; i < 33; ++i) {
      const double tx = std::max(0.0, 1 - std::abs(da.x(i) - 32) / 16),
                   ty = std::max(0.0, 1 - std::abs(da.y(j) - 32) / 16);
      EXPECT_NEAR(out->at(i, j), 2 * tx * ty, 1e-6) << i << "," << j;
    }
  EXPECT_EQ(out->at(16, 16), 2.0f);
}

TEST(Resample, SameLatticeCopiesExactly) {
  // A tile and its parent share a lattice; resampling between them copies values bit for bit.
  const Domain whole = Domain::from_extent({-1000.3, 77.7}, {2000, 2000}, {129, 129});
  auto src = std::make_shared<Heightfield>(whole);
  for (std::size_t k = 0; k < src->data.size(); ++k) src->data[k] = std::sin(0.37f * static_cast<float>(k));
  const Domain tile = whole.subdomain(17, 33, 40, 50);
  const Heightfield t = resample_bilinear(*src, tile);
  for (int j = 0; j < 50; ++j)
    for (int i = 0; i < 40; ++i) ASSERT_EQ(t.at(i, j), src->at(17 + i, 33 + j));
  // And onto an unrelated lattice of the same rectangle at 2x - 1 resolution every other sample is exact.
  const Heightfield fine = resample_bilinear(*src, whole.resampled({257, 257}));
  for (int j = 0; j < 129; j += 5)
    for (int i = 0; i < 129; i += 3) ASSERT_EQ(fine.at(2 * i, 2 * j), src->at(i, j));
}

TEST(FieldFunctions, MatchTheNodes) {
  const Domain d = Domain::from_extent({0, 0}, {50, 50}, {9, 9});
  const auto a = make_field(d, [](double x, double y) { return x - y; });
  const auto b =
      make_field(Domain::from_extent({0, 0}, {50, 50}, {4, 4}), [](double x, double y) { return x * 0.1 + y; });
  const Heightfield sum = add_fields(*a, *b, {1.5, 2.0});
  const auto node_sum =
      run_node("Add", d, {{"weight_a", 1.5}, {"weight_b", 2.0}}, {{"a", a}, {"b", b}}).get<Heightfield>();
  EXPECT_EQ(sum.data, node_sum->data);
  const Heightfield prod = multiply_fields(*a, *b, {0.5});
  const auto node_prod = run_node("Multiply", d, {{"scale", 0.5}}, {{"a", a}, {"b", b}}).get<Heightfield>();
  EXPECT_EQ(prod.data, node_prod->data);
}

}  // namespace
}  // namespace orogen
