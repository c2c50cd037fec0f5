// The SIMD noise kernels against the scalar reference, on every instruction set they were compiled for
// that this CPU supports (scalar, SSE4, AVX2, AVX-512), plus thread-count independence and the lattice
// split at extreme coordinates.
#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <hwy/targets.h>
#include <tbb/task_arena.h>

#include <gtest/gtest.h>

#include "nodes/noise/fbm.h"
#include "nodes/noise/lattice_hash.h"
#include "nodes/noise/lattice_noise.h"
#include "nodes/noise/noise_field.h"
#include "nodes/noise/noise_kernels.h"
#include "nodes/noise/noise_reference.h"
#include "nodes/noise/worley.h"

namespace orogen {
namespace {

using namespace noise;

struct NamedPlan {
  std::string name;
  NoisePlan plan;
};

std::vector<NamedPlan> plans() {
  std::vector<NamedPlan> out;
  LatticeNoiseParams lp;
  lp.feature_size = 83.0;
  lp.amplitude = 1.0;
  lp.seed = 42;
  for (Basis b : {Basis::Perlin, Basis::Simplex, Basis::Value, Basis::White})
    out.push_back({std::string(kBasisNames[static_cast<int>(b)]), lattice_noise_plan(b, lp)});
  for (WorleyMetric m : {WorleyMetric::Euclidean, WorleyMetric::Manhattan, WorleyMetric::Chebyshev})
    for (WorleyOutput o : {WorleyOutput::F1, WorleyOutput::F1TimesF2, WorleyOutput::MeanF1ToF4}) {
      WorleyParams wp;
      wp.feature_size = 61.0;
      wp.amplitude = 1.0;
      wp.metric = m;
      wp.output = o;
      wp.jitter = 0.9;
      out.push_back({"worley " + std::string(kWorleyMetricNames[static_cast<int>(m)]) + " " +
                         std::string(kWorleyOutputNames[static_cast<int>(o)]),
                     worley_plan(wp)});
    }
  for (FractalMode mode :
       {FractalMode::Fbm, FractalMode::Ridged, FractalMode::Billow, FractalMode::Hybrid, FractalMode::Multifractal})
    for (Basis b : {Basis::Perlin, Basis::Simplex, Basis::Worley}) {
      FbmParams fp;
      fp.basis = b;
      fp.mode = mode;
      fp.feature_size = 400.0;
      fp.amplitude = 1.0;
      fp.octaves = b == Basis::Worley ? 3 : 5;
      fp.lacunarity = 2.1;
      fp.offset = 0.8;
      fp.seed = 9;
      out.push_back({"fbm " + std::string(kFractalModeNames[static_cast<int>(mode)]) + " " +
                         std::string(kBasisNames[static_cast<int>(b)]),
                     fbm_plan(fp)});
    }
  return out;
}

Heightfield random_field(const Domain& d, float lo, float hi, unsigned seed) {
  Heightfield f(d);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> dist(lo, hi);
  for (float& v : f.data) v = dist(rng);
  return f;
}

// Largest |kernel - reference| over the domain, relative to max(1, |reference|).
float worst_error(const Domain& d, const NoisePlan& plan, const NoiseInputs& in) {
  const Heightfield h = evaluate_noise(d, plan, in);
  float worst = 0.0f;
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) {
      ReferenceInputs r;
      if (in.warp_x) r.warp_x = in.warp_x->at(i, j);
      if (in.warp_y) r.warp_y = in.warp_y->at(i, j);
      if (in.roughness) r.roughness = in.roughness->at(i, j);
      if (in.amplitude) r.amplitude = in.amplitude->at(i, j);
      const float expected = evaluate_noise_reference(plan, d.x(i), d.y(j), r);
      worst = std::max(worst, std::fabs(h.at(i, j) - expected) / std::max(1.0f, std::fabs(expected)));
    }
  return worst;
}

class EveryTarget : public ::testing::Test {
 protected:
  void TearDown() override { hwy::SetSupportedTargetsForTest(0); }
};

TEST_F(EveryTarget, KernelsAgreeWithTheScalarReference) {
  // 300 columns: a full run of 256 and a padded tail; far from the origin.
  const Domain d = Domain::from_extent({1.23e5, -4.5e4}, {2990.0, 80.0}, {300, 9});
  const Heightfield wx = random_field(d, -200.0f, 200.0f, 1), wy = random_field(d, -200.0f, 200.0f, 2);
  const Heightfield rough = random_field(d, 0.0f, 1.0f, 3), amp = random_field(d, 0.5f, 2.0f, 4);
  const auto targets = kernels::available_targets();
  ASSERT_FALSE(targets.empty());
  for (std::int64_t target : targets) {
    hwy::SetSupportedTargetsForTest(target);
    ASSERT_STREQ(kernels::active_target(), kernels::target_name(target));
    for (const NamedPlan& p : plans()) {
      SCOPED_TRACE(std::string(kernels::target_name(target)) + " " + p.name);
      EXPECT_LT(worst_error(d, p.plan, {}), 1e-5f) << "unwarped";
      EXPECT_LT(worst_error(d, p.plan, {&wx, &wy, &rough, &amp}), 1e-5f) << "warped, with maps";
      EXPECT_LT(worst_error(d, p.plan, {nullptr, &wy, nullptr, nullptr}), 1e-5f) << "warped in y only";
    }
  }
}

TEST_F(EveryTarget, SimplexRowsAgreeWithTheReferenceAtEveryDensity) {
  // The unwarped simplex kernel takes its corners from a block of vertices hashed once per vector of columns
  // when a vector's rows stay inside it (dense sampling) and hashes them per sample otherwise: from 0.3 to
  // 160 samples per lattice unit both paths and the switch between them agree with the reference. Nine
  // rows: a block of eight and a row alone; far from the origin, on both sides of zero.
  for (std::int64_t target : kernels::available_targets()) {
    hwy::SetSupportedTargetsForTest(target);
    for (double feature : {3.0, 17.0, 61.0, 240.0, 1600.0}) {
      for (glm::dvec2 origin : {glm::dvec2(-805.0, -41.0), glm::dvec2(3.3e6, -7.1e5)}) {
        LatticeNoiseParams lp;
        lp.feature_size = feature;
        lp.amplitude = 1.0;
        lp.seed = 5;
        const Domain d = Domain::from_extent(origin, {2990.0, 80.0}, {300, 9});
        SCOPED_TRACE(std::string(kernels::target_name(target)) + " feature " + std::to_string(feature));
        EXPECT_LT(worst_error(d, lattice_noise_plan(Basis::Simplex, lp), {}), 1e-5f);
      }
    }
  }
}

TEST(NoiseKernels, ResultDoesNotDependOnTheThreadCount) {
  const Domain d = Domain::from_extent({0, 0}, {5000, 5000}, {333, 257});
  for (const NamedPlan& p : plans()) {
    const Heightfield many = evaluate_noise(d, p.plan);
    Heightfield one;
    tbb::task_arena arena(1);
    arena.execute([&] { one = evaluate_noise(d, p.plan); });
    EXPECT_EQ(many.data, one.data) << p.name;
  }
}

TEST(NoiseKernels, LatticeSplitMatchesTheReferenceAtExtremeCoordinates) {
  std::vector<double> u = {0.0,
                           -0.0,
                           1e-300,
                           -1e-300,
                           0.5,
                           -0.5,
                           -1.0,
                           1.0 - 1e-17,
                           4294967295.5,
                           4294967296.0,
                           -4294967296.25,
                           0x1.0p40 + 0.25,
                           -0x1.0p45 - 0.75,
                           1e15 + 0.5,
                           -3.75e9,
                           2147483647.5,
                           2147483648.5,
                           -2147483648.5};
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> wide(-1e12, 1e12);
  while (u.size() % kernels::kBatchAlign != 0 || u.size() < 64) u.push_back(wide(rng));
  std::vector<std::uint32_t> cell(u.size());
  std::vector<float> frac(u.size());
  for (std::int64_t target : kernels::available_targets()) {
    hwy::SetSupportedTargetsForTest(target);
    kernels::split_lattice(u.data(), kHashPrimeX, static_cast<int>(u.size()), cell.data(), frac.data());
    for (std::size_t k = 0; k < u.size(); ++k) {
      const auto r = reference::split(u[k]);
      EXPECT_EQ(cell[k], r.cell * kHashPrimeX) << kernels::target_name(target) << " u=" << u[k];
      EXPECT_EQ(frac[k], r.frac) << kernels::target_name(target) << " u=" << u[k];
      EXPECT_GE(frac[k], 0.0f);
      EXPECT_LE(frac[k], 1.0f);
    }
  }
  hwy::SetSupportedTargetsForTest(0);
  // Wrapping: cells 2^32 apart share their hash, and consecutive cells wrap around 2^32.
  EXPECT_EQ(reference::split(-1.0).cell, 0xFFFFFFFFu);
  EXPECT_EQ(reference::split(4294967296.0 + 3.0).cell, 3u);
}

TEST(NoiseKernels, FarFromTheOriginTheNoiseKeepsItsDetail) {
  // 10^7 m from the origin with 1 m features: the float fraction still resolves 0.1 m steps exactly as
  // near the origin (the same cells hash differently, but the statistics of the steps are the same).
  auto mean_step = [](glm::dvec2 origin) {
    LatticeNoiseParams p;
    p.feature_size = 1.0;
    p.amplitude = 1.0;
    const Domain d = Domain::from_extent(origin, {25.5, 25.5}, {256, 256});
    const Heightfield h = perlin(d, p);
    double s = 0;
    for (int j = 0; j < d.height(); ++j)
      for (int i = 1; i < d.width(); ++i) s += std::fabs(h.at(i, j) - h.at(i - 1, j));
    return s / (d.height() * (d.width() - 1));
  };
  const double near = mean_step({0, 0}), far = mean_step({1e7, -1e7});
  EXPECT_NEAR(far, near, 0.1 * near);
}

}  // namespace
}  // namespace orogen
