// Texture family: splat weights (sum to 1, rock on cliffs, snow above the line), ambient occlusion and
// cavity against analytic planes, hillshade (shade and image) against Lambert's law on planes, the color map
// (exact colors per layer, blending, precedence, shade), image channels and reductions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "evaluator/run_node.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/exec_context.h"
#include "nodes/climate/kmeans.h"
#include "nodes/common/categorical_palette.h"
#include "nodes/texture/color_layers.h"
#include "nodes/texture/image_channel.h"
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

// A plane of slope `slope_deg` whose downhill side faces `aspect_deg` (clockwise from north), z = 0 at the
// center sample.
Heightfield plane(double slope_deg, double aspect_deg) {
  Heightfield z(Domain::from_extent({0, 0}, {100, 100}, {11, 11}));
  const double t = std::tan(slope_deg * kDeg), dx = std::sin(aspect_deg * kDeg), dy = std::cos(aspect_deg * kDeg);
  for (int j = 0; j < 11; ++j)
    for (int i = 0; i < 11; ++i)
      z.at(i, j) = static_cast<float>(-t * (dx * (z.domain.x(i) - 50.0) + dy * (z.domain.y(j) - 50.0)));
  return z;
}

// Lambert's cosine law for the plane above under a sun at (azimuth, elevation): cos(incidence) =
// cos(slope) sin(elevation) + sin(slope) cos(elevation) cos(azimuth - aspect), 0 when the sun is behind.
double lambert(double slope, double aspect, double azimuth, double elevation) {
  const double c = std::cos(slope * kDeg) * std::sin(elevation * kDeg) +
                   std::sin(slope * kDeg) * std::cos(elevation * kDeg) * std::cos((azimuth - aspect) * kDeg);
  return std::max(0.0, c);
}

TEST(Hillshade, ImageIsLambertsCosineOnPlanesOfKnownSlopeAndAspect) {
  int shadowed = 0;
  for (double slope : {0.0, 10.0, 35.0, 70.0})
    for (double aspect : {0.0, 90.0, 200.0, 315.0})
      for (double azimuth : {0.0, 135.0, 315.0})
        for (double elevation : {5.0, 45.0, 80.0}) {
          const auto img = gray_image(*hillshade(plane(slope, aspect), azimuth, elevation, 1.0));
          const double expect = lambert(slope, aspect, azimuth, elevation);
          shadowed += expect == 0.0;
          const float* px = img->pixel(5, 5);
          for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(px[c], expect, 2e-5) << slope << " " << aspect << " " << azimuth << " " << elevation;
          if (expect == 0.0) {
            EXPECT_EQ(px[0], 0.0f) << "a slope facing away from the sun is black";
          }
          EXPECT_EQ(px[3], 1.0f);
        }
  EXPECT_GT(shadowed, 10) << "slopes facing away from the sun are among the cases";
  // Flat ground under any sun: sin(elevation).
  for (double elevation : {1.0, 30.0, 90.0})
    EXPECT_NEAR(gray_image(*hillshade(plane(0, 0), 77.0, elevation, 1.0))->pixel(3, 7)[0], std::sin(elevation * kDeg),
                1e-6);
  // z_factor steepens the plane: 20 degrees at z_factor 2 is atan(2 tan 20) degrees.
  const double steeper = std::atan(2.0 * std::tan(20 * kDeg)) / kDeg;
  EXPECT_NEAR(gray_image(*hillshade(plane(20, 90), 90, 30, 2.0))->pixel(5, 5)[0], lambert(steeper, 90, 90, 30), 2e-5);
}

TEST(Hillshade, GrayImageCopiesTheShadeIntoRgbWithOpaqueAlpha) {
  Heightfield v(Domain::from_extent({10, 20}, {30, 20}, {4, 3}));
  for (std::size_t q = 0; q < v.data.size(); ++q) v.data[q] = static_cast<float>(q) / 11.0f;
  const auto img = gray_image(v);
  ASSERT_EQ(img->channels, 4);
  EXPECT_EQ(img->domain.resolution, v.domain.resolution);
  EXPECT_EQ(img->domain.origin, v.domain.origin);
  EXPECT_EQ(img->channel_names, (std::vector<std::string>{"R", "G", "B", "A"}));
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 4; ++i) {
      const float* px = img->pixel(i, j);
      EXPECT_EQ(px[0], v.at(i, j));
      EXPECT_EQ(px[1], v.at(i, j));
      EXPECT_EQ(px[2], v.at(i, j));
      EXPECT_EQ(px[3], 1.0f);
    }
  // The node's image output is the gray image of its shade output.
  auto z = std::make_shared<Heightfield>(plane(30, 200));
  const auto run = run_node("Hillshade", z->domain, {{"sun_azimuth", 180.0}, {"sun_elevation", 40.0}},
                            {{"in", PortValue(HeightfieldPtr(z))}});
  const auto shade = run.get<Heightfield>(0);
  const auto image = run.get<Image>(1);
  for (int j = 0; j < 11; ++j)
    for (int i = 0; i < 11; ++i) EXPECT_EQ(image->pixel(i, j)[1], shade->at(i, j));
  EXPECT_NEAR(shade->at(5, 5), lambert(30, 200, 180, 40), 2e-5);
}

// Layer colors: distinct linear values, exactly representable.
const glm::vec4 kGrass(0.125f, 0.5f, 0.25f, 1.0f), kRock(0.5f, 0.375f, 0.25f, 1.0f),
    kRockLater(0.75f, 0.0625f, 1.0f, 1.0f);

Image weights(int w, int h, std::vector<std::string> names) {
  Image img(Domain::from_extent({0, 0}, {w - 1.0, h - 1.0}, {w, h}), static_cast<int>(names.size()));
  img.channel_names = std::move(names);
  return img;
}

void set_pixel(Image& img, int i, int j, std::initializer_list<float> v) {
  int c = 0;
  for (float x : v) img.pixel(i, j)[c++] = x;
}

void expect_rgb(const Image& img, int i, int j, const glm::vec4& c, float tol = 0.0f) {
  const float* px = img.pixel(i, j);
  EXPECT_NEAR(px[0], c.r, tol) << i << "," << j;
  EXPECT_NEAR(px[1], c.g, tol) << i << "," << j;
  EXPECT_NEAR(px[2], c.b, tol) << i << "," << j;
  EXPECT_EQ(px[3], 1.0f) << i << "," << j;
}

TEST(ColorByLayers, ExactColorPerLayerBlendingByWeightAndPrecedence) {
  // Channels grass, rock, mystery (no color given), and a fourth without a name.
  Image w(Domain::from_extent({0, 0}, {3, 1}, {4, 2}), 4);
  w.channel_names = {"grass", "rock", "mystery"};
  set_pixel(w, 0, 0, {1, 0, 0, 0});
  set_pixel(w, 1, 0, {0, 1, 0, 0});
  set_pixel(w, 2, 0, {0, 0, 1, 0});
  set_pixel(w, 3, 0, {0, 0, 0, 1});
  set_pixel(w, 0, 1, {0.25f, 0.75f, 0, 0});
  set_pixel(w, 1, 1, {2, 0, 0, 0});                 // weights are not normalized
  set_pixel(w, 2, 1, {std::nanf(""), 0.5f, 0, 0});  // a non-finite weight counts as 0
  set_pixel(w, 3, 1, {0, 0, 0, 0});
  ColorByLayersParams p;
  // Two entries name rock: the later one wins. An entry naming no channel changes nothing.
  p.colors = {{"rock", kRock}, {"grass", kGrass}, {"sand", {1, 1, 0, 1}}, {"rock", kRockLater}};
  const auto out = color_by_layers(w, nullptr, p);
  ASSERT_EQ(out->channels, 4);
  EXPECT_EQ(out->channel_names, (std::vector<std::string>{"R", "G", "B", "A"}));
  expect_rgb(*out, 0, 0, kGrass);
  expect_rgb(*out, 1, 0, kRockLater);
  expect_rgb(*out, 2, 0, categorical_linear(2));  // no color given: the categorical one of its index
  expect_rgb(*out, 3, 0, categorical_linear(3));  // no name at all
  expect_rgb(*out, 0, 1, 0.25f * kGrass + 0.75f * kRockLater, 1e-7f);
  expect_rgb(*out, 1, 1, 2.0f * kGrass);
  expect_rgb(*out, 2, 1, 0.5f * kRockLater);
  expect_rgb(*out, 3, 1, glm::vec4(0, 0, 0, 1));
  // The layer colors alone.
  const auto cols = layer_colors(w.channel_names, w.channels, p.colors);
  ASSERT_EQ(cols.size(), 4u);
  EXPECT_EQ(cols[0], kGrass);
  EXPECT_EQ(cols[1], kRockLater);
  EXPECT_EQ(cols[2], categorical_linear(2));
}

TEST(ColorByLayers, ShadeScalesByStrengthClampedAndNonFiniteIsUnshaded) {
  Image w = weights(4, 1, {"grass"});
  for (int i = 0; i < 4; ++i) set_pixel(w, i, 0, {1});
  Heightfield shade(w.domain);
  shade.at(0, 0) = 0.4f;
  shade.at(1, 0) = 1.7f;                                    // clamped to 1
  shade.at(2, 0) = -3.0f;                                   // clamped to 0
  shade.at(3, 0) = std::numeric_limits<float>::infinity();  // not finite: unshaded
  ColorByLayersParams p;
  p.colors = {{"grass", kGrass}};
  for (double strength : {0.0, 0.5, 1.0}) {
    p.shade_strength = strength;
    const auto out = color_by_layers(w, &shade, p);
    const auto factor = [&](double s) { return static_cast<float>(1.0 - strength + strength * s); };
    expect_rgb(*out, 0, 0, factor(0.4) * kGrass, 1e-7f);
    expect_rgb(*out, 1, 0, kGrass);
    expect_rgb(*out, 2, 0, factor(0.0) * kGrass, 1e-7f);
    expect_rgb(*out, 3, 0, kGrass);
  }
  // The library takes the shade on the weights' grid only (the node resamples it first), with the shared
  // precondition's message naming the input.
  Heightfield other(Domain::from_extent({0, 0}, {3, 1}, {5, 2}));
  try {
    color_by_layers(w, &other, p);
    ADD_FAILURE() << "accepted a shade on another grid";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("shade ("), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("must lie on the primary grid"), std::string::npos) << e.what();
  }
}

// A ColorByLayers.colors table: (layer name, sRGB color) rows.
TableValue layer_color_rows(std::vector<std::pair<std::string, Srgb8>> rows) {
  TableValue t{{"name", "color"}, {}};
  for (auto& [name, color] : rows) t.rows.push_back({name, color});
  return t;
}

TEST(ColorByLayers, NodeReadsSrgbHexColorsByLayerName) {
  auto w = std::make_shared<Image>(weights(2, 2, {"dirt", "snow"}));
  set_pixel(*w, 0, 0, {1, 0});
  set_pixel(*w, 1, 0, {0, 1});
  const auto out = run_node("ColorByLayers", w->domain,
                            {{"colors", layer_color_rows({{"snow", {255, 255, 255}}, {"dirt", {0, 0, 0}}})}},
                            {{"in", PortValue(ImagePtr(w))}})
                       .get<Image>();
  expect_rgb(*out, 0, 0, glm::vec4(0, 0, 0, 1));
  expect_rgb(*out, 1, 0, glm::vec4(1, 1, 1, 1));
  // sRGB 0x80 is 0.2158605 linear.
  const auto gray = run_node("ColorByLayers", w->domain, {{"colors", layer_color_rows({{"dirt", {0x80, 0x80, 0x80}}})}},
                             {{"in", PortValue(ImagePtr(w))}})
                        .get<Image>();
  expect_rgb(*gray, 0, 0, glm::vec4(0.2158605f, 0.2158605f, 0.2158605f, 1), 1e-6f);
}

// Channel c of sample (i, j) holds 100 c + 10 j + i + 0.25, so every value is distinct and exact.
Image channels_image() {
  Image img = weights(4, 3, {"red", "green", "blue"});
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 4; ++i)
      for (int c = 0; c < 3; ++c) img.pixel(i, j)[c] = static_cast<float>(100 * c + 10 * j + i) + 0.25f;
  return img;
}

TEST(ImageChannel, EachChannelExtractedExactlyByIndexAndByName) {
  const Image img = channels_image();
  const char* names[] = {"red", "green", "blue"};
  for (int c = 0; c < 3; ++c) {
    ImageChannelParams by_index;
    by_index.index = c;
    ImageChannelParams by_name;
    by_name.name = names[c];
    by_name.index = 2 - c;  // ignored when a name is given
    for (const auto& p : {by_index, by_name}) {
      const auto f = image_channel(img, p);
      EXPECT_EQ(f->domain.resolution, img.domain.resolution);
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 4; ++i) EXPECT_EQ(f->at(i, j), static_cast<float>(100 * c + 10 * j + i) + 0.25f);
    }
  }
}

TEST(ImageChannel, ReductionsOverTheChannels) {
  Image img = channels_image();
  img.pixel(2, 1)[1] = -7.5f;  // a minimum in the middle channel
  for (ChannelMode mode : {ChannelMode::Mean, ChannelMode::Sum, ChannelMode::Min, ChannelMode::Max}) {
    ImageChannelParams p;
    p.mode = mode;
    const auto f = image_channel(img, p);
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 4; ++i) {
        const float* px = img.pixel(i, j);
        const double sum = static_cast<double>(px[0]) + px[1] + px[2];
        const double expect = mode == ChannelMode::Mean  ? sum / 3.0
                              : mode == ChannelMode::Sum ? sum
                              : mode == ChannelMode::Min ? std::min({px[0], px[1], px[2]})
                                                         : std::max({px[0], px[1], px[2]});
        EXPECT_EQ(f->at(i, j), static_cast<float>(expect)) << static_cast<int>(mode) << " " << i << "," << j;
      }
  }
}

TEST(ImageChannel, UnknownNameOrIndexBeyondTheChannelsIsRefused) {
  const Image img = channels_image();
  ImageChannelParams p;
  p.name = "alpha";
  try {
    image_channel(img, p);
    ADD_FAILURE() << "an unknown channel name was accepted";
  } catch (const NodeError& e) {
    EXPECT_NE(std::string(e.what()).find("red, green, blue"), std::string::npos) << e.what();
  }
  p.name.clear();
  p.index = 3;
  EXPECT_THROW(image_channel(img, p), NodeError);
  p.index = -1;
  EXPECT_THROW(image_channel(img, p), NodeError);
  // Through the node: a bad name stops the node too.
  auto shared = std::make_shared<Image>(img);
  EXPECT_THROW(
      run_node("ImageChannel", img.domain, {{"name", std::string("alpha")}}, {{"in", PortValue(ImagePtr(shared))}}),
      NodeError);
  EXPECT_EQ(run_node("ImageChannel", img.domain, {{"name", std::string("blue")}}, {{"in", PortValue(ImagePtr(shared))}})
                .get<Heightfield>()
                ->at(3, 2),
            223.25f);
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
