// Texture family: splat weights (sum to 1, rock on cliffs, snow above the line), ambient occlusion and
// cavity against analytic planes, hillshade, the colour map.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "evaluator/run_node.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/table_json.h"

#include <nlohmann/json.hpp>
#include "nodes/texture/shading.h"
#include "nodes/texture/splat.h"
#include "support/key_checks.h"

namespace orogen::texture {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A constructed mountain, 20 m spacing, 3180 m east-west: a plain at 0 m (x < 600), a 60-degree cliff up to
// 400 m, a 5-degree slope to x = 1500, a 60-degree cliff up 1700 m, then a flat summit plateau above 2000 m.
double mountain_height(double x) {
  const double t60 = std::tan(60 * kDeg), t5 = std::tan(5 * kDeg);
  const double c1 = 600.0 + 400.0 / t60, top1 = 400.0 + (1500.0 - c1) * t5, c2 = 1500.0 + 1700.0 / t60;
  if (x < 600.0) return 0.0;
  if (x < c1) return (x - 600.0) * t60;
  if (x < 1500.0) return 400.0 + (x - c1) * t5;
  if (x < c2) return top1 + (x - 1500.0) * t60;
  return top1 + 1700.0;
}

Heightfield mountain() {
  Heightfield z(Domain::from_extent({0, 0}, {3180, 1260}, {160, 64}));
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 160; ++i) z.at(i, j) = static_cast<float>(mountain_height(z.domain.x(i)));
  return z;
}

// SplatWeights' layers from its two tables, written as in a graph file.
std::vector<SplatLayer> splat_layers(const char* layers, const char* rules) {
  return splat_layers_from_tables(table_from_json_text(layers, splat_layer_schema()),
                                  table_from_json_text(rules, splat_rule_schema()));
}

TEST(Splat, WeightsSumToOneRockOnCliffsSnowAboveTheLine) {
  const Heightfield z = mountain();
  const auto layers = splat_layers_from_tables(default_splat_layers(), default_splat_rules());
  ASSERT_EQ(layers.size(), 5u);
  const auto r = splat_weights({&z}, layers);
  ASSERT_EQ(r.weights->channels, 5);
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 160; ++i) {
      const float* w = r.weights->pixel(i, j);
      double sum = 0.0;
      for (int l = 0; l < 5; ++l) {
        EXPECT_GE(w[l], 0.0f);
        sum += w[l];
      }
      ASSERT_NEAR(sum, 1.0, 1e-5);
      // Packed splat maps carry the same weights.
      for (int l = 0; l < 4; ++l) EXPECT_EQ(r.splat[0]->pixel(i, j)[l], w[l]);
      EXPECT_EQ(r.splat[1]->pixel(i, j)[0], w[4]);
    }
  auto dominant = [&](double x) { return r.dominant->at(static_cast<int>(std::lround(x / 20.0)), 32); };
  EXPECT_EQ(dominant(700), 2.0f) << "rock on the lower 60-degree cliff";
  EXPECT_EQ(dominant(2000), 2.0f) << "rock on the upper cliff";
  EXPECT_EQ(dominant(300), 4.0f) << "sand on the plain at 0 m";
  EXPECT_EQ(dominant(1200), 0.0f) << "grass on the 5-degree slope at 430 m";
  EXPECT_EQ(dominant(3000), 3.0f) << "snow on the plateau above 2000 m";
}

TEST(Splat, TermsAndTables) {
  SplatTerm t{SplatInput::Slope, true, 30.0, 5.0};
  EXPECT_EQ(splat_term(t, 20.0), 0.0);
  EXPECT_EQ(splat_term(t, 40.0), 1.0);
  EXPECT_NEAR(splat_term(t, 30.0), 0.5, 1e-12);
  t.greater = false;
  EXPECT_NEAR(splat_term(t, 26.0), 1.0 - splat_term({SplatInput::Slope, true, 30.0, 5.0}, 26.0), 1e-12);
  t.softness = 0.0;
  EXPECT_EQ(splat_term(t, 29.999), 1.0);
  EXPECT_EQ(splat_term(t, 30.0), 0.0);
  EXPECT_EQ(splat_term(t, std::nan("")), 0.0);
  // Rules attach to their layer in table order, whatever the order of the layers.
  const auto l = splat_layers(R"([{"name": "a", "weight": 0.5}, {"name": "b", "weight": 1}])",
                              R"([{"layer": "b", "input": "slope", "compare": "<", "threshold": 7, "softness": 0},
                                  {"layer": "a", "input": "height", "compare": ">", "threshold": 10, "softness": 2},
                                  {"layer": "b", "input": "flow", "compare": ">", "threshold": 0.5,
                                   "softness": 0.1}])");
  ASSERT_EQ(l.size(), 2u);
  EXPECT_EQ(l[0].name, "a");
  EXPECT_EQ(l[0].weight, 0.5);
  ASSERT_EQ(l[0].terms.size(), 1u);
  EXPECT_EQ(l[0].terms[0].input, SplatInput::Height);
  EXPECT_TRUE(l[0].terms[0].greater);
  EXPECT_EQ(l[0].terms[0].threshold, 10.0);
  EXPECT_EQ(l[0].terms[0].softness, 2.0);
  ASSERT_EQ(l[1].terms.size(), 2u);
  EXPECT_EQ(l[1].terms[0].input, SplatInput::Slope);
  EXPECT_FALSE(l[1].terms[0].greater);
  EXPECT_EQ(l[1].terms[1].input, SplatInput::Flow);
  try {
    splat_layers(R"([{"name": "a", "weight": 1}])",
                 R"([{"layer": "a", "input": "height", "compare": ">", "threshold": 1, "softness": 0},
                     {"layer": "rock", "input": "height", "compare": ">", "threshold": 1, "softness": 0}])");
    ADD_FAILURE() << "a rule of no layer was accepted";
  } catch (const NodeError& e) {
    EXPECT_STREQ(e.what(), "rules[1].layer: 'rock' is not a layer of the layers table");
  }
  // The schema bounds the layers to 1..8 and refuses a negative softness or an unknown input, naming the cell.
  TableProblem problem;
  EXPECT_FALSE(table_from_json(nlohmann::json::parse("[]"), splat_layer_schema(), problem));
  EXPECT_EQ(problem.str("layers"), "layers: at least 1 row(s) needed, found 0");
  EXPECT_FALSE(table_from_json(nlohmann::json::parse(R"([{"name": "a", "weight": 1}, {"name": "b", "weight": 1},
      {"name": "c", "weight": 1}, {"name": "d", "weight": 1}, {"name": "e", "weight": 1}, {"name": "f", "weight": 1},
      {"name": "g", "weight": 1}, {"name": "h", "weight": 1}, {"name": "i", "weight": 1}])"),
                               splat_layer_schema(), problem));
  EXPECT_EQ(problem.str("layers"), "layers: at most 8 rows allowed, found 9");
  EXPECT_FALSE(table_from_json(
      nlohmann::json::parse(R"([{"layer": "a", "input": "slope", "compare": ">", "threshold": 3, "softness": -1}])"),
      splat_rule_schema(), problem));
  EXPECT_EQ(problem.str("rules"), "rules[0].softness: -1 is below the minimum 0");
  EXPECT_FALSE(table_from_json(
      nlohmann::json::parse(R"([{"layer": "a", "input": "heigth", "compare": ">", "threshold": 3, "softness": 1}])"),
      splat_rule_schema(), problem));
  EXPECT_EQ(problem.str("rules"),
            "rules[0].input: 'heigth' is not one of: height, slope, curvature, flow, wetness, field");
  // A rule on an unconnected input is an error; all-zero weights go to the first layer.
  const Heightfield z = mountain();
  EXPECT_THROW(splat_weights({&z}, splat_layers(R"([{"name": "a", "weight": 1}])",
                                                R"([{"layer": "a", "input": "flow", "compare": ">", "threshold": 0.5,
                                                     "softness": 0}])")),
               NodeError);
  const auto r =
      splat_weights({&z}, splat_layers(R"([{"name": "a", "weight": 1}, {"name": "b", "weight": 1}])",
                                       R"([{"layer": "a", "input": "height", "compare": ">", "threshold": 1e9,
                                            "softness": 0},
                                           {"layer": "b", "input": "height", "compare": ">", "threshold": 1e9,
                                            "softness": 0}])"));
  EXPECT_EQ(r.weights->pixel(5, 5)[0], 1.0f);
  EXPECT_EQ(r.weights->pixel(5, 5)[1], 0.0f);
}

// AO and cavity on a tilted plane are exact: every distance sees the same tangent tan(b) cos(theta).
TEST(Shading, AmbientOcclusionAndCavityOnPlanes) {
  for (double beta : {0.0, 20.0, 45.0}) {
    Heightfield z(Domain::from_extent({0, 0}, {630, 630}, {64, 64}));
    for (int j = 0; j < 64; ++j)
      for (int i = 0; i < 64; ++i) z.at(i, j) = static_cast<float>(std::tan(beta * kDeg) * z.domain.x(i));
    const int D = 16;
    const auto m = horizon_maps(z, 100.0, D);
    double expect = 0.0;
    for (int k = 0; k < D; ++k) {
      const double t = std::tan(beta * kDeg) * std::cos(2 * std::numbers::pi * k / D);
      expect += 1.0 - std::max(0.0, t / std::sqrt(1 + t * t));
    }
    expect /= D;
    EXPECT_NEAR(m.ao->at(32, 32), expect, 1e-4) << beta;
    EXPECT_NEAR(m.cavity->at(32, 32), 0.5, 1e-4) << beta;
  }
}

TEST(Shading, OcclusionInPitsCavityInValleysAndOnRidges) {
  // V-shaped valley along y at x = 320 m, walls at 30 degrees.
  Heightfield v(Domain::from_extent({0, 0}, {630, 630}, {64, 64}));
  for (int j = 0; j < 64; ++j)
    for (int i = 0; i < 64; ++i) v.at(i, j) = static_cast<float>(std::abs(v.domain.x(i) - 320.0) * std::tan(30 * kDeg));
  const auto m = horizon_maps(v, 150.0, 16);
  EXPECT_LT(m.ao->at(32, 32), m.ao->at(20, 32)) << "the valley floor sees less sky than the valley side";
  EXPECT_LT(m.cavity->at(32, 32), 0.5f) << "a valley is a cavity";
  // Inverted: a ridge is brighter than a plane.
  for (auto& h : v.data) h = -h;
  const auto r = horizon_maps(v, 150.0, 16);
  EXPECT_GT(r.cavity->at(32, 32), 0.5f);
  EXPECT_NEAR(r.ao->at(32, 32), 1.0, 1e-6) << "nothing above a ridge crest";
}

TEST(Shading, HillshadeFacingTheLightIsOne) {
  Heightfield flat(Domain::from_extent({0, 0}, {100, 100}, {11, 11}), 5.0f);
  EXPECT_NEAR(hillshade(flat, 315, 45, 1)->at(5, 5), std::sin(45 * kDeg), 1e-6);
  // A plane rising to the south-east faces north-west, tilted 45 degrees: facing a light at 315 deg, 45 deg.
  Heightfield p(flat.domain);
  const double g = 1.0 / std::sqrt(2.0);
  for (int j = 0; j < 11; ++j)
    for (int i = 0; i < 11; ++i) p.at(i, j) = static_cast<float>(g * p.domain.x(i) - g * p.domain.y(j));
  EXPECT_NEAR(hillshade(p, 315, 45, 1)->at(5, 5), 1.0, 1e-6);
  EXPECT_NEAR(hillshade(p, 135, 45, 1)->at(5, 5), 0.0, 1e-6);
}

TEST(Texture, NodesRunAndKeys) {
  const Domain d = Domain::from_extent({0, 0}, {3180, 1260}, {160, 64});
  auto z = std::make_shared<Heightfield>(mountain());
  const auto s = run_node("SplatWeights", d, {}, {{"in", PortValue(HeightfieldPtr(z))}});
  const auto ao = run_node("AmbientOcclusion", d, {}, {{"in", PortValue(HeightfieldPtr(z))}});
  const auto c = run_node("ColorByLayers", d, {}, {{"in", s.outputs[0]}, {"shade", ao.outputs[0]}});
  const auto img = c.get<Image>(0);
  ASSERT_EQ(img->channels, 4);
  // On the snow field (weights one-hot snow, nothing occluding) the color is the snow color.
  const float* px = img->pixel(150, 32);
  EXPECT_GT(px[0], 0.8f);
  EXPECT_GT(px[2], 0.8f);
  const Domain small = Domain::from_extent({0, 0}, {640, 640}, {17, 17});
  for (const char* type : {"SplatWeights", "AmbientOcclusion", "Cavity", "Hillshade", "ColorByLayers"}) {
    expect_every_param_changes_key(type, small);
    expect_every_input_changes_key(type, small);
  }
}

}  // namespace
}  // namespace orogen::texture
