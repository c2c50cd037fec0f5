// Tests of the example node library with the Orogen testing kit: the algorithm's properties, and the
// contracts every Orogen node passes.
#include <cmath>
#include <set>

#include <orogen/testing.h>

#include "terraced_canyon.h"

namespace {

using canyon::canyon_cut;
using canyon::CanyonParams;

TEST(TerracedCanyon, PassesTheNodeContracts) { orogen::kit::expect_node_contracts("TerracedCanyon"); }

// The extremes contract alone, with a budget of its own (a slow simulation would want a longer one).
TEST(TerracedCanyon, ExtremeParametersGiveAFiniteResultOrAClearError) {
  orogen::contracts::ExtremesOptions o;
  o.budget_seconds = 10.0;
  orogen::kit::expect_extremes("TerracedCanyon", o);
}

TEST(TerracedCanyon, CutsDepthOnTheCentreLineAndNothingBeyondTheRim) {
  CanyonParams p;
  for (double x : {-1234.0, 0.0, 77.0, 400.0}) {
    const double center = p.center_y + p.amplitude * std::sin(2.0 * M_PI * x / p.wavelength);
    EXPECT_DOUBLE_EQ(canyon_cut(x, center, p), p.depth) << x;
    EXPECT_EQ(canyon_cut(x, center + 0.5 * p.width + 1e-6, p), 0.0) << x;
    EXPECT_EQ(canyon_cut(x, center - 0.5 * p.width - 50.0, p), 0.0) << x;
  }
}

TEST(TerracedCanyon, WallsAreStaircasesOfWholeTerraces) {
  CanyonParams p;
  p.amplitude = 0.0;
  std::set<double> levels;
  double previous = p.depth;
  for (double y = 0.0; y <= 0.5 * p.width; y += 0.25) {
    const double cut = canyon_cut(0.0, y, p);
    EXPECT_LE(cut, previous) << "the cut never deepens towards the rim, y " << y;
    EXPECT_NEAR(std::remainder(cut, p.terrace), 0.0, 1e-9) << "on a whole terrace, y " << y;
    levels.insert(cut);
    previous = cut;
  }
  EXPECT_EQ(levels.size(), static_cast<std::size_t>(p.depth / p.terrace) + 1) << "every bench from floor to rim";
  p.terrace = 0.0;  // smooth walls take values between the steps
  EXPECT_GT(std::abs(std::remainder(canyon_cut(0.0, 0.35 * p.width, p), 10.0)), 1e-3);
}

TEST(TerracedCanyon, TheNodeSubtractsTheCutFromItsInput) {
  const auto d = orogen::kit::domain(1000.0, 41, {-500.0, -500.0});
  const auto in = orogen::kit::field(d, [](double x, double y) { return 300.0 + 0.1 * x - 0.05 * y; });
  const auto run = orogen::kit::run("TerracedCanyon", d, {{"depth", 80.0}, {"terrace", 20.0}}, {{"in", in}});
  const auto out = orogen::kit::output_field(run);
  const auto& h = *std::get<orogen::HeightfieldPtr>(in);
  CanyonParams p;
  p.depth = 80.0;
  p.terrace = 20.0;
  int cut_samples = 0;
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) {
      const double expected = h.at(i, j) - canyon_cut(d.x(i), d.y(j), p);
      EXPECT_FLOAT_EQ(out->at(i, j), static_cast<float>(expected));
      cut_samples += out->at(i, j) < h.at(i, j);
    }
  EXPECT_GT(cut_samples, 41) << "the canyon crosses the domain";
  EXPECT_LT(cut_samples, 41 * 41 / 2) << "and leaves most of it alone";
}

}  // namespace
