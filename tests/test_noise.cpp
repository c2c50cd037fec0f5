// Noise generators (Perlin, Simplex, Value, White, FBM) through their nodes and their scalar references:
// known values, bounds, continuity, determinism, tiles, resolution independence, warping, cache keys.
// Worley has its own file (test_noise_worley.cpp), the SIMD kernels theirs (test_noise_kernels.cpp).
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "evaluator/run_node.h"
#include "graph/exec_context.h"
#include "nodes/noise/fbm.h"
#include "nodes/noise/lattice_hash.h"
#include "nodes/noise/lattice_noise.h"
#include "nodes/noise/noise_reference.h"
#include "support/key_checks.h"

namespace orogen {
namespace {

using Params = std::map<std::string, ParamValue>;
using Inputs = std::map<std::string, PortValue>;

HeightfieldPtr eval(const std::string& type, const Domain& d, const Params& p = {}, const Inputs& in = {}) {
  return run_node(type, d, p, in).get<Heightfield>();
}

HeightfieldPtr constant_field(const Domain& d, float v) { return std::make_shared<Heightfield>(d, v); }

// The samples [i0, i0 + w) x [j0, j0 + h) of f, on the corresponding subdomain.
HeightfieldPtr cut(const Heightfield& f, int i0, int j0, int w, int h) {
  auto out = std::make_shared<Heightfield>(f.domain.subdomain(i0, j0, w, h));
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) out->at(i, j) = f.at(i0 + i, j0 + j);
  return out;
}

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0, mb = 0;
  for (std::size_t k = 0; k < a.size(); ++k) ma += a[k], mb += b[k];
  ma /= static_cast<double>(a.size());
  mb /= static_cast<double>(b.size());
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    sab += (a[k] - ma) * (b[k] - mb);
    saa += (a[k] - ma) * (a[k] - ma);
    sbb += (b[k] - mb) * (b[k] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

struct Generator {
  std::string type;
  Params params;
  std::string name() const {
    std::string s = type;
    for (const auto& [k, v] : params)
      if (const auto* str = std::get_if<std::string>(&v)) s += " " + k + "=" + *str;
    return s;
  }
};

// Every generator, and each fractal mode once, with features of about 300 m.
std::vector<Generator> generators() {
  const double fs = 300.0;
  return {
      {"Perlin", {{"feature_size", fs}}},
      {"Simplex", {{"feature_size", fs}}},
      {"Value", {{"feature_size", fs}}},
      {"White", {{"feature_size", fs}}},
      {"Worley", {{"feature_size", fs}, {"output", std::string("f2_minus_f1")}}},
      {"Worley",
       {{"feature_size", fs},
        {"metric", std::string("manhattan")},
        {"output", std::string("mean_f1_f4")},
        {"jitter", 0.7}}},
      {"Worley", {{"feature_size", fs}, {"metric", std::string("chebyshev")}, {"output", std::string("f1_times_f2")}}},
      {"FBM", {{"feature_size", 4 * fs}, {"octaves", std::int64_t{4}}}},
      {"FBM",
       {{"feature_size", 4 * fs},
        {"basis", std::string("simplex")},
        {"mode", std::string("ridged")},
        {"octaves", std::int64_t{4}}}},
      {"FBM",
       {{"feature_size", 4 * fs},
        {"basis", std::string("value")},
        {"mode", std::string("billow")},
        {"octaves", std::int64_t{4}}}},
      {"FBM",
       {{"feature_size", 4 * fs},
        {"basis", std::string("worley")},
        {"mode", std::string("hybrid")},
        {"octaves", std::int64_t{3}},
        {"offset", 0.7}}},
      {"FBM",
       {{"feature_size", 4 * fs},
        {"mode", std::string("multifractal")},
        {"octaves", std::int64_t{5}},
        {"roughness", 0.6}}},
  };
}

// ---------------------------------------------------------------------------------------------------
// Perlin

TEST(Perlin, ZeroAtEveryLatticePoint) {
  // 4 samples per cell: every 4th sample is a lattice point. Far from the origin to exercise precision.
  const double fs = 64.0;
  const Domain d = Domain::from_extent({-3.0e6, 7.0e6}, {fs * 32, fs * 32}, {129, 129});
  const auto h = eval("Perlin", d, {{"feature_size", fs}, {"amplitude", 1.0}, {"seed", std::uint64_t{11}}});
  float largest_elsewhere = 0.0f;
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) {
      if (i % 4 == 0 && j % 4 == 0)
        EXPECT_EQ(h->at(i, j), 0.0f) << i << "," << j;
      else
        largest_elsewhere = std::max(largest_elsewhere, std::fabs(h->at(i, j)));
    }
  EXPECT_GT(largest_elsewhere, 0.3f);  // and it is not zero everywhere
}

// Value on both sides of a cell border, and one-sided second-order derivatives across it.
struct BorderCheck {
  float jump, slope_jump;
};
template <class F>
BorderCheck across_border(F f, double k, double other, bool along_x) {
  auto g = [&](double t) { return static_cast<double>(along_x ? f(k + t, other) : f(other, k + t)); };
  const double e = 1e-6, h = 1e-2;
  const double right = (-3 * g(0) + 4 * g(h) - g(2 * h)) / (2 * h);
  const double left = (3 * g(0) - 4 * g(-h) + g(-2 * h)) / (2 * h);
  return {static_cast<float>(std::fabs(g(e) - g(-e))), static_cast<float>(std::fabs(right - left))};
}

TEST(Perlin, ContinuousWithContinuousGradientAcrossCellBorders) {
  const std::uint32_t key = noise::stream_key(5, noise::Stream::Perlin);
  auto perlin = [&](double u, double v) { return noise::reference::perlin(u, v, key); };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> frac(0.0, 1.0);
  std::uniform_int_distribution<int> cell(-1000, 1000);
  float worst_jump = 0, worst_slope = 0, typical_slope = 0;
  for (int n = 0; n < 2000; ++n) {
    const double k = cell(rng), other = cell(rng) + frac(rng);
    for (bool along_x : {true, false}) {
      const auto c = across_border(perlin, k, other, along_x);
      worst_jump = std::max(worst_jump, c.jump);
      worst_slope = std::max(worst_slope, c.slope_jump);
      typical_slope = std::max(typical_slope, std::fabs(perlin(k + 0.01, other) - perlin(k, other)) / 0.01f);
    }
  }
  EXPECT_LT(worst_jump, 1e-4f);
  EXPECT_LT(worst_slope, 0.05f);   // one-sided slopes agree (the fade's derivative vanishes at borders)
  EXPECT_GT(typical_slope, 0.5f);  // while the slopes themselves are of order 1
}

TEST(Perlin, NodeAgreesAcrossACellBorderAtFineSpacing) {
  // A fine strip of samples straddling x = 2 * feature_size: the node's values are continuous there too.
  const double fs = 100.0;
  const Domain d = Domain::from_extent({2 * fs - 0.5, 37.0}, {1.0, 0.0}, {101, 1});
  const auto h = eval("Perlin", d, {{"feature_size", fs}, {"amplitude", 1.0}});
  for (int i = 1; i < d.width(); ++i) EXPECT_LT(std::fabs(h->at(i, 0) - h->at(i - 1, 0)), 1e-3f);
}

// ---------------------------------------------------------------------------------------------------
// Bounds over 10^6 samples

void expect_bounded(const std::string& type, float lo, float hi, float must_reach) {
  const Domain d = Domain::from_extent({123.0, -456.0}, {7770.0, 7770.0}, {1000, 1000});  // 7.77 samples per cell
  const auto h = eval(type, d, {{"feature_size", 60.0}, {"amplitude", 1.0}, {"seed", std::uint64_t{99}}});
  const auto [mn, mx] = std::minmax_element(h->data.begin(), h->data.end());
  EXPECT_GE(*mn, lo - 1e-6f) << type;
  EXPECT_LE(*mx, hi + 1e-6f) << type;
  EXPECT_GT(std::max(-*mn, *mx), must_reach) << type << " uses too little of its range";
}

TEST(Perlin, BoundedByAmplitudeOverAMillionSamples) { expect_bounded("Perlin", -1.0f, 1.0f, 0.95f); }
TEST(Simplex, BoundedByAmplitudeOverAMillionSamples) { expect_bounded("Simplex", -1.0f, 1.0f, 0.95f); }
TEST(Value, BoundedByAmplitudeOverAMillionSamples) { expect_bounded("Value", -1.0f, 1.0f, 0.95f); }
TEST(White, BoundedByAmplitudeOverAMillionSamples) { expect_bounded("White", -1.0f, 1.0f, 0.99f); }

// ---------------------------------------------------------------------------------------------------
// Simplex

TEST(Simplex, ZeroAtLatticeVerticesBecauseOtherCornersAreBeyondTheRadius) {
  // At a vertex of the simplex lattice its own corner contributes 0 (d = 0) and every other vertex is at
  // least an edge (sqrt(2/3)) away, beyond the radius sqrt(1/2): the sum is exactly 0 up to rounding.
  const std::uint32_t key = noise::stream_key(8, noise::Stream::Simplex);
  for (int i = -20; i <= 20; i += 3)
    for (int j = -20; j <= 20; j += 4) {
      const double t = (i + j) * noise::reference::kSimplexG2;
      EXPECT_NEAR(noise::reference::simplex(i - t, j - t, key), 0.0f, 1e-5f) << i << "," << j;
    }
}

TEST(Simplex, ContinuousAcrossSimplexBorders) {
  const std::uint32_t key = noise::stream_key(9, noise::Stream::Simplex);
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> pos(-50.0, 50.0);
  float worst = 0;
  for (int n = 0; n < 20000; ++n) {
    const double u = pos(rng), v = pos(rng), e = 1e-6;
    worst =
        std::max(worst, std::fabs(noise::reference::simplex(u + e, v, key) - noise::reference::simplex(u - e, v, key)));
  }
  EXPECT_LT(worst, 1e-3f);
}

// ---------------------------------------------------------------------------------------------------
// White and Value

TEST(White, ConstantInsideACellAndUniformAcrossCells) {
  const double fs = 10.0;
  const Domain d = Domain::from_extent({0.5, 0.5}, {fs * 200 - 1.0, fs * 200 - 1.0}, {1000, 1000});  // ~2 m apart
  const auto h = eval("White", d, {{"feature_size", fs}, {"amplitude", 1.0}});
  double sum = 0, sum2 = 0;
  std::size_t same_cell = 0, new_cell = 0, new_cell_changed = 0;
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) {
      const float v = h->at(i, j);
      sum += v;
      sum2 += static_cast<double>(v) * v;
      if (i == 0) continue;
      if (std::floor(d.x(i) / fs) == std::floor(d.x(i - 1) / fs)) {
        ++same_cell;
        if (v != h->at(i - 1, j)) ADD_FAILURE() << "value changes inside a cell at " << i << "," << j;
      } else {
        ++new_cell;
        new_cell_changed += v != h->at(i - 1, j);
      }
      if (::testing::Test::HasFailure()) return;
    }
  EXPECT_GT(same_cell, 3 * new_cell);
  EXPECT_GT(new_cell_changed, new_cell * 99 / 100);  // independent cells
  const double n = static_cast<double>(d.sample_count());
  EXPECT_NEAR(sum / n, 0.0, 0.02);         // 40000 cells: mean of U(-1, 1)
  EXPECT_NEAR(sum2 / n, 1.0 / 3.0, 0.02);  // and its variance
}

TEST(Value, TakesItsLatticeValuesAtLatticePoints) {
  const std::uint32_t key = noise::stream_key(0, noise::Stream::Value);
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j) {
      const float expected =
          noise::unit_float(noise::lattice_hash(static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j), key)) *
              2.0f -
          1.0f;
      EXPECT_FLOAT_EQ(noise::reference::value(i, j, key), expected);
    }
}

// ---------------------------------------------------------------------------------------------------
// FBM

TEST(FBM, OneOctaveEqualsItsBasis) {
  const Domain d = Domain::from_extent({-700, 300}, {3000, 2000}, {150, 100});
  const std::map<std::string, std::string> basis_node{
      {"perlin", "Perlin"}, {"simplex", "Simplex"}, {"value", "Value"}, {"worley", "Worley"}};
  for (const auto& [basis, node] : basis_node) {
    const auto single = eval(node, d, {{"feature_size", 230.0}, {"amplitude", 55.0}, {"seed", std::uint64_t{4}}});
    const auto fractal = eval("FBM", d,
                              {{"basis", basis},
                               {"octaves", std::int64_t{1}},
                               {"feature_size", 230.0},
                               {"amplitude", 55.0},
                               {"seed", std::uint64_t{4}},
                               {"gain", 0.3}});
    EXPECT_EQ(single->data, fractal->data) << basis;
  }
}

TEST(FBM, ModesStayInTheirDocumentedRanges) {
  const Domain d = Domain::from_extent({0, 0}, {20000, 20000}, {400, 400});
  struct Case {
    std::string mode;
    float lo, hi;
  };
  for (const Case& c : {Case{"fbm", -1, 1}, Case{"billow", -1, 1}, Case{"ridged", 0, 1}}) {
    for (const char* basis : {"perlin", "simplex", "value"}) {
      const auto h = eval("FBM", d,
                          {{"mode", c.mode},
                           {"basis", std::string(basis)},
                           {"amplitude", 1.0},
                           {"feature_size", 800.0},
                           {"octaves", std::int64_t{6}}});
      const auto [mn, mx] = std::minmax_element(h->data.begin(), h->data.end());
      EXPECT_GE(*mn, c.lo - 1e-5f) << c.mode << " " << basis;
      EXPECT_LE(*mx, c.hi + 1e-5f) << c.mode << " " << basis;
      EXPECT_GT(*mx - *mn, 0.2f * (c.hi - c.lo)) << c.mode << " " << basis;
    }
  }
}

TEST(FBM, MultifractalFollows002Equation4) {
  // With R = 0 everywhere, Eq 4 weighs octave k by r^-k: the un-normalised fBm with gain 1/r.
  const Domain d = Domain::from_extent({0, 0}, {5000, 5000}, {120, 120});
  const double r = 2.0;
  const Params common{{"feature_size", 900.0},
                      {"octaves", std::int64_t{5}},
                      {"lacunarity", r},
                      {"amplitude", 1.0},
                      {"seed", std::uint64_t{21}}};
  Params mf = common, fb = common;
  mf["mode"] = std::string("multifractal");
  fb["gain"] = 1.0 / r;
  const auto multi = eval("FBM", d, mf, {{"roughness", constant_field(d, 0.0f)}});
  const auto plain = eval("FBM", d, fb);
  const double norm = 1 + 1 / r + 1 / (r * r) + 1 / (r * r * r) + 1 / (r * r * r * r);
  for (std::size_t k = 0; k < multi->data.size(); ++k) ASSERT_NEAR(multi->data[k], plain->data[k] * norm, 1e-4) << k;

  // R = 1: every octave at full weight; the roughness map overrides the parameter where connected.
  Params mf1 = mf;
  mf1["roughness"] = 1.0;
  const auto by_param = eval("FBM", d, mf1);
  const auto by_map = eval("FBM", d, mf, {{"roughness", constant_field(d, 1.0f)}});
  for (std::size_t k = 0; k < by_param->data.size(); ++k) ASSERT_NEAR(by_param->data[k], by_map->data[k], 1e-5);

  // The amplitude map A multiplies the result.
  const auto doubled = eval("FBM", d, mf1, {{"amplitude", constant_field(d, 2.0f)}});
  for (std::size_t k = 0; k < by_param->data.size(); ++k) ASSERT_FLOAT_EQ(doubled->data[k], 2.0f * by_param->data[k]);
}

TEST(FBM, RougherMapsGiveRougherTerrain) {
  const Domain d = Domain::from_extent({0, 0}, {4000, 4000}, {256, 256});
  auto roughness_of = [&](float r) {
    const auto h = eval("FBM", d,
                        {{"mode", std::string("multifractal")},
                         {"feature_size", 1000.0},
                         {"amplitude", 1.0},
                         {"octaves", std::int64_t{6}}},
                        {{"roughness", constant_field(d, r)}});
    double s = 0;  // mean squared second difference: the energy of the fine octaves
    for (int j = 0; j < d.height(); ++j)
      for (int i = 1; i + 1 < d.width(); ++i) {
        const double dd = h->at(i - 1, j) - 2.0 * h->at(i, j) + h->at(i + 1, j);
        s += dd * dd;
      }
    return s;
  };
  const double smooth = roughness_of(0.1f), rough = roughness_of(0.7f);
  EXPECT_GT(rough, 4.0 * smooth);
}

TEST(FBM, OctaveLatticesDoNotLineUp) {
  // At the lattice points of octave 0 Perlin vanishes; with lacunarity 2 the finer octaves' lattices would
  // vanish there too (a visible grid of zeros) unless each octave is shifted, as fbm_plan does.
  const double fs = 256.0;
  const Domain d = Domain::from_extent({0, 0}, {fs * 40, fs * 40}, {41, 41});  // one sample per lattice point
  const auto h = eval("FBM", d, {{"feature_size", fs}, {"octaves", std::int64_t{5}}, {"amplitude", 1.0}});
  std::size_t clearly_nonzero = 0;
  for (float v : h->data) clearly_nonzero += std::fabs(v) > 0.01f;
  EXPECT_GT(clearly_nonzero, h->data.size() * 3 / 4);
}

TEST(FBM, RejectsWhiteBasisAndBadOctaves) {
  noise::FbmParams p;
  p.basis = noise::Basis::White;
  EXPECT_THROW(noise::fbm_plan(p), NodeError);
  p.basis = noise::Basis::Perlin;
  p.octaves = 0;
  EXPECT_THROW(noise::fbm_plan(p), NodeError);
}

// ---------------------------------------------------------------------------------------------------
// Every generator

TEST(NoiseGenerators, SameSeedBitIdenticalDifferentSeedDifferent) {
  const Domain d = Domain::from_extent({-100, -100}, {3000, 3000}, {97, 61});
  for (const Generator& g : generators()) {
    Params a = g.params, b = g.params;
    a["seed"] = std::uint64_t{12345};
    b["seed"] = std::uint64_t{12346};
    const auto first = eval(g.type, d, a), again = eval(g.type, d, a), other = eval(g.type, d, b);
    EXPECT_EQ(first->data, again->data) << g.name();
    std::size_t differing = 0;
    for (std::size_t k = 0; k < first->data.size(); ++k) differing += first->data[k] != other->data[k];
    EXPECT_GT(differing, first->data.size() * 9 / 10) << g.name();
  }
}

TEST(NoiseGenerators, TileOfALargeEvaluationEqualsTheTileEvaluated) {
  const Domain big = Domain::from_extent({-1000, 500}, {5000, 5000}, {1024, 1024});
  const int i0 = 389, j0 = 517, n = 256;  // not a multiple of the vector width: tails and offsets differ
  const Domain tile = big.subdomain(i0, j0, n, n);
  for (const Generator& g : generators()) {
    const auto whole = eval(g.type, big, g.params);
    const auto part = eval(g.type, tile, g.params);
    EXPECT_EQ(cut(*whole, i0, j0, n, n)->data, part->data) << g.name();
  }
  // Warped: the tile of the warp fields gives the tile of the warped noise.
  const auto wx = eval("Perlin", big, {{"feature_size", 700.0}, {"amplitude", 150.0}, {"seed", std::uint64_t{1}}});
  const auto wy = eval("Perlin", big, {{"feature_size", 700.0}, {"amplitude", 150.0}, {"seed", std::uint64_t{2}}});
  for (const Generator& g : generators()) {
    const auto whole = eval(g.type, big, g.params, {{"warp_x", wx}, {"warp_y", wy}});
    const auto part =
        eval(g.type, tile, g.params, {{"warp_x", cut(*wx, i0, j0, n, n)}, {"warp_y", cut(*wy, i0, j0, n, n)}});
    EXPECT_EQ(cut(*whole, i0, j0, n, n)->data, part->data) << g.name() << " warped";
  }
}

TEST(NoiseGenerators, ResolutionIndependent512And2048AgreeAfterDownsampling) {
  const Domain coarse = Domain::from_extent({-3000, 1000}, {8192, 8192}, {512, 512});
  const Domain fine = coarse.resampled({2048, 2048});
  for (Generator g : generators()) {
    if (g.type == "White") g.params["feature_size"] = 1000.0;  // cells of 60 coarse samples: few border samples
    const auto lo = eval(g.type, coarse, g.params);
    const auto hi = eval(g.type, fine, g.params);
    std::vector<double> a, b;
    for (int j = 0; j < coarse.height(); ++j)
      for (int i = 0; i < coarse.width(); ++i) {
        a.push_back(lo->at(i, j));
        b.push_back(hi->sample_world(coarse.x(i), coarse.y(j)));
      }
    EXPECT_GT(correlation(a, b), 0.99) << g.name();
  }
}

TEST(NoiseGenerators, ConstantWarpEqualsAShiftedEvaluation) {
  const Domain d = Domain::from_extent({250, -125}, {2500, 2500}, {131, 77});
  const glm::dvec2 shift{37.5, -12.25};
  Domain shifted = d;
  shifted.origin += shift;
  for (const Generator& g : generators()) {
    Params p = g.params;
    p["amplitude"] = 1.0;
    const auto warped = eval(
        g.type, d, p, {{"warp_x", constant_field(d, float(shift.x))}, {"warp_y", constant_field(d, float(shift.y))}});
    const auto moved = eval(g.type, shifted, p);
    float worst = 0;
    for (std::size_t k = 0; k < warped->data.size(); ++k)
      worst = std::max(worst, std::fabs(warped->data[k] - moved->data[k]));
    EXPECT_LT(worst, 1e-4f) << g.name();
    // Warping by a constant really moves the noise (the inputs are not ignored).
    const auto plain = eval(g.type, d, p);
    EXPECT_NE(plain->data, warped->data) << g.name();
  }
}

// The grid rule (nodes/common/match_domain.h): a warp field on another grid is resampled onto the requested
// domain (a constant stays that constant), and one that does not overlap it is refused.
TEST(NoiseGenerators, ResamplesWarpFieldsOfAnotherResolution) {
  const Domain d = Domain::from_extent({0, 0}, {1000, 1000}, {64, 64});
  const auto small = constant_field(d.resampled({32, 32}), 7.5f);
  EXPECT_EQ(eval("Perlin", d, {}, {{"warp_x", small}})->data,
            eval("Perlin", d, {}, {{"warp_x", constant_field(d, 7.5f)}})->data);
  const auto far = constant_field(Domain::from_extent({5000, 5000}, {1000, 1000}, {32, 32}), 7.5f);
  EXPECT_THROW(eval("Perlin", d, {}, {{"warp_x", far}}), NodeError);
}

TEST(NoiseGenerators, EveryParameterAndInputChangesTheCacheKey) {
  const Domain d = Domain::from_extent({0, 0}, {1000, 1000}, {32, 32});
  for (const char* type : {"Perlin", "Simplex", "Value", "White", "Worley", "FBM"}) {
    SCOPED_TRACE(type);
    expect_every_param_changes_key(type, d);
    expect_every_input_changes_key(type, d);
  }
}

}  // namespace
}  // namespace orogen
