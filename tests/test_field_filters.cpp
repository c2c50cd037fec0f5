// Blur and Warp: conservation, the Gaussian's width in metres at two resolutions, exact identities of
// the Catmull-Rom warp.
#include <cmath>
#include <numbers>
#include <numeric>

#include <gtest/gtest.h>

#include "field_ops_fixtures.h"
#include "nodes/field/bicubic.h"
#include "nodes/field/blur.h"
#include "nodes/field/resample_field.h"
#include "nodes/field/warp.h"

namespace orogen {
namespace {

using test::field_from;
using test::run_field;

double sum(const Heightfield& f) { return std::accumulate(f.data.begin(), f.data.end(), 0.0); }

// The field's integral over its rectangle by the trapezoid rule (border samples are shared with the
// neighbouring tile, so they count half), divided by the area.
double trapezoid_mean(const Heightfield& f) {
  double s = 0;
  const int w = f.width(), h = f.height();
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i)
      s += f.at(i, j) * ((i == 0 || i == w - 1) ? 0.5 : 1.0) * ((j == 0 || j == h - 1) ? 0.5 : 1.0);
  return s / ((w - 1.0) * (h - 1.0));
}

TEST(Blur, PreservesAConstantWithBothKernelsAndEdges) {
  const Domain d = Domain::from_extent({0, 0}, {1000, 600}, {101, 61});  // 10 m spacing
  const auto c = field_from(d, [](double, double) { return 123.25; });
  for (double sigma : {5.0, 60.0, 400.0, 2000.0}) {  // 0.5, 6 samples: direct; 40, 200 samples: decimated
    for (const char* edges : {"clamp", "mirror"}) {
      const auto out = run_field("Blur", d, {{"sigma", sigma}, {"edges", std::string(edges)}}, {{"in", c}});
      for (float v : out->data) ASSERT_NEAR(v, 123.25, 123.25 * 1e-6) << sigma << " " << edges;
    }
  }
}

TEST(Blur, MirrorEdgesPreserveTheIntegralExactly) {
  const Domain d = Domain::from_extent({0, 0}, {800, 500}, {161, 101});  // 5 m spacing
  const auto noise = field_from(
      d, [&](double x, double y) { return 100.0 * test::hash01(std::llround(x), std::llround(y)) + 0.2 * x; });
  for (double sigma : {12.0, 45.0}) {  // 2.4 and 9 samples: direct kernel, exact
    const auto out = run_field("Blur", d, {{"sigma", sigma}, {"edges", std::string("mirror")}}, {{"in", noise}});
    EXPECT_NEAR(trapezoid_mean(*out) / trapezoid_mean(*noise), 1.0, 1e-6) << sigma;
  }
  for (double sigma : {150.0, 600.0}) {  // 30 and 120 samples: decimated evaluation
    const auto out = run_field("Blur", d, {{"sigma", sigma}, {"edges", std::string("mirror")}}, {{"in", noise}});
    EXPECT_NEAR(trapezoid_mean(*out) / trapezoid_mean(*noise), 1.0, 1e-4) << sigma;
  }
}

TEST(Blur, ClampEdgesPreserveTheSumOfAnInteriorBump) {
  // Far from the edges the clamp rule never matters, so the blur conserves mass exactly there.
  const Domain d = Domain::from_extent({0, 0}, {2000, 2000}, {201, 201});
  const auto bump = field_from(d, [](double x, double y) {
    const double r = std::hypot(x - 1000, y - 1000);
    return r < 200
               ? 50.0 * (1 + std::cos(r / 200 * std::numbers::pi)) + 7 * test::hash01(std::llround(x), std::llround(y))
               : 0.0;
  });
  for (double sigma : {30.0, 160.0}) {  // 3 samples: direct; 16 samples: decimated. 4 sigma + 200 m < 1000 m
    const auto out = run_field("Blur", d, {{"sigma", sigma}}, {{"in", bump}});
    EXPECT_NEAR(sum(*out) / sum(*bump), 1.0, 1e-5) << sigma;
  }
}

// The blur of a unit impulse (integral 1 m^2) is the Gaussian density with the given sigma in metres.
void check_impulse(int n, double sigma, double tolerance_of_peak) {
  const double size = 1000.0;
  const Domain d = Domain::from_extent({0, 0}, {size, size}, {n, n});
  const double cell = d.spacing.x * d.spacing.y;
  auto impulse = std::make_shared<Heightfield>(d);
  impulse->at(n / 2, n / 2) = static_cast<float>(1.0 / cell);
  const auto out = run_field("Blur", d, {{"sigma", sigma}}, {{"in", impulse}});
  const double cx = d.x(n / 2), cy = d.y(n / 2);
  const double peak = 1.0 / (2 * std::numbers::pi * sigma * sigma);
  double mass = 0, m2x = 0, m2y = 0, worst = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double dx = d.x(i) - cx, dy = d.y(j) - cy, v = out->at(i, j);
      mass += v * cell;
      m2x += v * cell * dx * dx;
      m2y += v * cell * dy * dy;
      const double g = peak * std::exp(-(dx * dx + dy * dy) / (2 * sigma * sigma));
      worst = std::max(worst, std::abs(v - g));
    }
  EXPECT_NEAR(mass, 1.0, 1e-5) << n;
  EXPECT_NEAR(std::sqrt(m2x), sigma, 0.005 * sigma) << n;  // standard deviation in metres along x
  EXPECT_NEAR(std::sqrt(m2y), sigma, 0.005 * sigma) << n;
  EXPECT_LT(worst, tolerance_of_peak * peak) << n;
}

TEST(Blur, ImpulseIsAGaussianWithSigmaInMetresAtTwoResolutions) {
  // 40 m is 8 samples at 201^2 (direct kernel) and 32 samples at 801^2 (decimated evaluation).
  check_impulse(201, 40.0, 0.002);
  check_impulse(801, 40.0, 0.002);
}

TEST(Blur, LineKernelIsTheGaussianOnBothSidesOfTheSwitch) {
  // The 1D response to an impulse against the continuous Gaussian density, for sigmas from the direct
  // kernel through the switch to the decimated evaluation (15 samples) and far beyond.
  const int n = 6001;
  std::vector<float> impulse(n, 0.0f), out(n);
  impulse[n / 2] = 1.0f;
  for (double sigma : {3.0, 11.9, 14.9, 15.1, 19.0, 23.9, 29.0, 47.5, 100.0, 333.0}) {
    gaussian_blur_line(impulse.data(), out.data(), n, sigma, BlurEdges::Clamp);
    const double peak = 1.0 / (std::sqrt(2 * std::numbers::pi) * sigma);
    double worst = 0, mass = 0, m2 = 0;
    for (int i = 0; i < n; ++i) {
      const double x = i - n / 2;
      worst = std::max(worst, std::abs(out[i] - peak * std::exp(-x * x / (2 * sigma * sigma))));
      mass += out[i];
      m2 += out[i] * x * x;
    }
    EXPECT_LT(worst, 4e-4 * peak) << sigma;
    EXPECT_NEAR(mass, 1.0, 1e-5) << sigma;
    EXPECT_NEAR(std::sqrt(m2), sigma, 1e-3 * sigma) << sigma;
  }
}

TEST(Blur, TwoResolutionsAgreeOnCoincidingSamples) {
  const Domain coarse = Domain::from_extent({0, 0}, {2048, 2048}, {257, 257});
  const Domain fine = coarse.resampled({1025, 1025});
  const auto a = run_field("Blur", coarse, {{"sigma", 60.0}}, {{"in", field_from(coarse, test::rolling_hills)}});
  const auto b = run_field("Blur", fine, {{"sigma", 60.0}}, {{"in", field_from(fine, test::rolling_hills)}});
  double worst = 0;
  for (int j = 0; j < 257; ++j)
    for (int i = 0; i < 257; ++i) worst = std::max(worst, std::abs(double(a->at(i, j)) - b->at(4 * i, 4 * j)));
  EXPECT_LT(worst, 0.5);  // metres, on ~600 m of relief
}

TEST(Blur, ZeroSigmaCopies) {
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {21, 21});
  const auto in = field_from(d, test::rolling_hills);
  EXPECT_TRUE(test::bit_identical(run_field("Blur", d, {{"sigma", 0.0}}, {{"in", in}})->data, in->data));
}

TEST(Resample, FixedSpacingWhateverTheRequestedResolution) {
  for (int n : {257, 1025}) {
    const Domain d = Domain::from_extent({100, -50}, {4096, 2048}, {n, (n + 1) / 2});
    const auto out = run_field("Resample", d, {{"spacing", 32.0}}, {{"in", field_from(d, test::rolling_hills)}});
    ASSERT_EQ(out->domain.resolution, glm::ivec2(129, 65)) << n;
    EXPECT_DOUBLE_EQ(out->domain.spacing.x, 32.0);
    EXPECT_EQ(out->domain.min_corner(), d.min_corner());
    EXPECT_EQ(out->domain.max_corner(), d.max_corner());
    // Output samples coincide with input samples (32 m is a multiple of 16 m and 4 m): exact copies.
    for (int j = 0; j < 65; j += 8)
      for (int i = 0; i < 129; i += 8) {
        const auto s = d.to_sample(out->domain.position(i, j));
        ASSERT_EQ(out->at(i, j), field_from(d, test::rolling_hills)
                                     ->at(static_cast<int>(std::lround(s.x)), static_cast<int>(std::lround(s.y))));
      }
  }
  // Spacing that does not divide the extent: rounded sample count, borders kept.
  const Domain d = Domain::from_extent({0, 0}, {1000, 1000}, {101, 101});
  const Domain r = resampled_domain(d, 30.0);
  EXPECT_EQ(r.resolution, glm::ivec2(34, 34));  // round(33.3) + 1
  EXPECT_EQ(r.max_corner(), d.max_corner());
}

TEST(Resample, PrefilterRemovesDetailTheCoarseLatticeCannotHold) {
  // A 20 m wave sampled at 16 m would alias into a false long wave; the prefilter suppresses it.
  const Domain d = Domain::from_extent({0, 0}, {2048, 256}, {1025, 129});  // 2 m
  const auto wave = field_from(d, [](double x, double) { return 10.0 * std::sin(2 * std::numbers::pi * x / 20.0); });
  const auto raw = run_field("Resample", d, {{"spacing", 16.0}}, {{"in", wave}});
  const auto filtered = run_field("Resample", d, {{"spacing", 16.0}, {"prefilter", true}}, {{"in", wave}});
  double raw_amp = 0, filtered_amp = 0;
  for (int j = 0; j < raw->height(); ++j)
    for (int i = 8; i < raw->width() - 8; ++i) {  // away from the mirrored edges
      raw_amp = std::max(raw_amp, double(std::abs(raw->at(i, j))));
      filtered_amp = std::max(filtered_amp, double(std::abs(filtered->at(i, j))));
    }
  EXPECT_GT(raw_amp, 5.0);
  // Gaussian response at a 20 m wavelength with sigma 8 m: exp(-2 pi^2 64 / 400) = 0.042.
  EXPECT_NEAR(filtered_amp, 10.0 * 0.042, 0.05);
}

TEST(Warp, ZeroDisplacementIsTheIdentity) {
  const Domain d = Domain::from_extent({0, 0}, {640, 480}, {65, 49});
  const auto in = field_from(d, test::rolling_hills);
  const auto zero = field_from(d, [](double, double) { return 0.0; });
  EXPECT_TRUE(test::bit_identical(run_field("Warp", d, {}, {{"in", in}, {"dx", zero}, {"dy", zero}})->data, in->data));
  EXPECT_TRUE(test::bit_identical(run_field("Warp", d, {}, {{"in", in}})->data, in->data));
}

TEST(Warp, ConstantDisplacementIsAShift) {
  const Domain d = Domain::from_extent({0, 0}, {640, 480}, {65, 49});  // 10 m spacing
  const auto in = field_from(d, test::rolling_hills);
  const auto dx = field_from(d, [](double, double) { return 30.0; });   // 3 samples
  const auto dy = field_from(d, [](double, double) { return -20.0; });  // -2 samples
  const auto out = run_field("Warp", d, {}, {{"in", in}, {"dx", dx}, {"dy", dy}});
  for (int j = 2; j < 49; ++j)
    for (int i = 0; i < 62; ++i) ASSERT_EQ(out->at(i, j), in->at(i + 3, j - 2)) << i << "," << j;
  // Beyond the edge the lookup clamps.
  EXPECT_EQ(out->at(64, 10), in->at(64, 8));
  // A fractional shift of a linear ramp is exact (Catmull-Rom reproduces linear functions), and strength
  // scales the displacement.
  const auto ramp = field_from(d, [](double x, double y) { return 0.5 * x - 0.25 * y; });
  const auto frac = run_field("Warp", d, {{"strength", 0.5}},
                              {{"in", ramp}, {"dx", field_from(d, [](double, double) { return 7.0; })}});
  for (int j = 0; j < 49; ++j)
    for (int i = 1; i < 60; ++i) ASSERT_NEAR(frac->at(i, j), 0.5 * (d.x(i) + 3.5) - 0.25 * d.y(j), 1e-4);
}

TEST(Warp, CatmullRomInterpolatesAndIsSmooth) {
  const Domain d = Domain::from_extent({0, 0}, {100, 100}, {11, 11});
  const auto in = field_from(d, test::rolling_hills);
  for (int j = 0; j < 11; ++j)
    for (int i = 0; i < 11; ++i) EXPECT_EQ(static_cast<float>(catmull_rom(*in, i, j)), in->at(i, j));
  // A quadratic in x is reproduced exactly in the interior (the cubic's tangents are exact there).
  const auto quad = field_from(d, [](double x, double) { return 0.01 * x * x; });
  for (double u = 1.0; u <= 8.0; u += 0.125)
    EXPECT_NEAR(catmull_rom(*quad, u, 5.0), 0.01 * (10 * u) * (10 * u), 1e-3) << u;
}

}  // namespace
}  // namespace orogen
