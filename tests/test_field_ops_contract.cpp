// The contract every field operator and shape keeps: bit-identical results for any thread count, the same
// terrain at any resolution (a 257^2 and a 1025^2 evaluation of one domain agree on their common samples),
// and (with tests/support/key_checks.h) every parameter in the cache key.
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "field_ops_fixtures.h"
#include "graph/registry.h"
#include "support/key_checks.h"

namespace orogen {
namespace {

using test::field_from;
using InputFn = std::function<PortValue(const Domain&)>;

PortValue hills(const Domain& d) { return PortValue(HeightfieldPtr(field_from(d, test::rolling_hills))); }
PortValue hills2(const Domain& d) {
  return PortValue(
      HeightfieldPtr(field_from(d, [](double x, double y) { return 150.0 * std::cos((x - y) / 410.0) + 0.03 * y; })));
}
PortValue mask(const Domain& d) {
  return PortValue(
      HeightfieldPtr(field_from(d, [](double x, double y) { return 0.5 + 0.5 * std::sin(x / 380.0 + y / 520.0); })));
}
PortValue displacement(const Domain& d) {
  return PortValue(HeightfieldPtr(
      field_from(d, [](double x, double y) { return 40.0 * std::sin(y / 290.0) + 10.0 * std::cos(x / 350.0); })));
}

struct Case {
  std::string name;  // test label
  std::string type;
  std::map<std::string, ParamValue> params;
  std::map<std::string, InputFn> inputs;
  double tolerance = 1e-6;     // resolution independence: max |coarse - fine| over the coarse output's range
  bool fixed_lattice = false;  // the output lattice does not follow the request (Resample): compare 1:1
};

std::vector<Case> cases() {
  const std::map<std::string, InputFn> one{{"in", hills}};
  const std::map<std::string, InputFn> two{{"a", hills}, {"b", hills2}};
  const std::map<std::string, InputFn> height{{"in", hills}};
  return {
      {"Subtract", "Subtract", {}, two},
      {"Min", "Min", {}, two},
      {"Max", "Max", {}, two},
      {"BlendLerp",
       "Blend",
       {{"mode", std::string("lerp")}, {"factor", 0.7}},
       {{"a", hills}, {"b", hills2}, {"mask", mask}}},
      {"BlendScreen", "Blend", {{"mode", std::string("screen")}}, {{"a", mask}, {"b", mask}}},
      {"Remap",
       "Remap",
       {{"in_min", -100.0}, {"in_max", 400.0}, {"out_min", 0.0}, {"out_max", 1.0}, {"clamp", true}},
       one},
      {"Clamp", "Clamp", {{"min", 0.0}, {"max", 150.0}}, one},
      {"Normalize", "Normalize", {{"min", 0.0}, {"max", 1000.0}}, one, 2e-3},
      {"Curve", "Curve", {{"input_min", -200.0}, {"input_max", 400.0}}, one},
      {"CurveFieldRange", "Curve", {{"range", std::string("field")}}, one, 2e-3},
      {"Power", "Power", {{"exponent", 1.5}, {"pivot", 50.0}, {"scale", 200.0}}, one},
      {"TerraceCount", "Terrace", {{"levels", std::int64_t{6}}, {"range_min", 0.0}, {"range_max", 300.0}}, one},
      {"TerraceSpacing", "Terrace", {{"mode", std::string("spacing")}, {"spacing", 25.0}, {"sharpness", 1.0}}, one},
      {"Invert", "Invert", {{"pivot", 10.0}}, one},
      {"Abs", "Abs", {}, one},
      {"SmoothStep", "SmoothStep", {{"edge0", 0.0}, {"edge1", 200.0}}, one},
      {"Threshold", "Threshold", {{"level", 60.0}}, one},
      {"BandMask", "BandMask", {{"min", 50.0}, {"max", 150.0}, {"falloff", 40.0}}, one},
      {"Blur", "Blur", {{"sigma", 40.0}}, one, 2e-3},
      {"BlurMirrorWide", "Blur", {{"sigma", 150.0}, {"edges", std::string("mirror")}}, one, 2e-3},
      {"Warp", "Warp", {{"strength", 1.5}}, {{"in", hills}, {"dx", displacement}, {"dy", displacement}}, 3e-3},
      {"Slope", "Slope", {}, height, 3e-3},
      {"AspectNorthness", "Aspect", {{"output", std::string("northness")}}, height, 1e-2},
      {"CurvatureProfile", "Curvature", {{"type", std::string("profile")}}, height, 2e-2},
      {"CurvatureMean", "Curvature", {{"type", std::string("mean")}}, height, 2e-2},
      {"Normals", "Normals", {}, height, 1e-3},
      {"ColorRamp", "ColorRamp", {{"input_min", -200.0}, {"input_max", 500.0}}, one},
      {"RadialFalloff",
       "RadialFalloff",
       {{"center", glm::dvec2(1000, 900)}, {"radius", 800.0}},
       {{"distance_offset", displacement}}},
      {"Cone", "Cone", {{"center", glm::dvec2(1000, 900)}, {"radius", 700.0}, {"height", 300.0}}, {}},
      {"Resample", "Resample", {{"spacing", 32.0}}, one, 1e-6, true},
      {"ResamplePrefilter", "Resample", {{"spacing", 20.0}, {"prefilter", true}}, one, 2e-3, true},
  };
}

// Output 0 of the node as a flat list of samples (all channels for images).
std::vector<float> samples(const NodeRun& run) {
  const auto& v = run.outputs.at(0);
  if (const auto* h = std::get_if<HeightfieldPtr>(&v)) return (*h)->data;
  if (const auto* img = std::get_if<ImagePtr>(&v)) return (*img)->data;
  ADD_FAILURE() << "unexpected output type";
  return {};
}

NodeRun run_case(const Case& c, const Domain& d) {
  std::map<std::string, PortValue> in;
  for (const auto& [name, fn] : c.inputs) in[name] = fn(d);
  return run_node(c.type, d, c.params, in);
}

class FieldOpContract : public ::testing::TestWithParam<Case> {};

TEST_P(FieldOpContract, BitIdenticalForOneAndSeveralThreads) {
  const Case& c = GetParam();
  const Domain d = Domain::from_extent({-300, 200}, {2100, 1500}, {301, 213});
  const auto one = test::with_threads(1, [&] { return samples(run_case(c, d)); });
  const auto several = test::with_threads(test::several_threads(), [&] { return samples(run_case(c, d)); });
  ASSERT_FALSE(one.empty());
  EXPECT_TRUE(test::bit_identical(one, several));
}

TEST_P(FieldOpContract, CoarseAndFineEvaluationsAgree) {
  const Case& c = GetParam();
  const Domain coarse = Domain::from_extent({0, 0}, {2048, 2048}, {257, 257});  // 8 m
  const Domain fine = coarse.resampled({1025, 1025});                           // 2 m: every 4th sample coincides
  const auto a = samples(run_case(c, coarse));
  const auto b = samples(run_case(c, fine));
  std::vector<double> va, vb;
  if (c.fixed_lattice) {
    ASSERT_EQ(a.size(), b.size());
    va.assign(a.begin(), a.end());
    vb.assign(b.begin(), b.end());
  } else {
    const std::size_t channels = a.size() / coarse.sample_count();
    ASSERT_EQ(b.size(), fine.sample_count() * channels);
    for (int j = 0; j < 257; ++j)
      for (int i = 0; i < 257; ++i)
        for (std::size_t k = 0; k < channels; ++k) {
          va.push_back(a[(static_cast<std::size_t>(j) * 257 + i) * channels + k]);
          vb.push_back(b[(static_cast<std::size_t>(4 * j) * 1025 + 4 * i) * channels + k]);
        }
  }
  const auto [lo, hi] = std::minmax_element(va.begin(), va.end());
  const double range = std::max(*hi - *lo, 1e-12);
  double worst = 0;
  for (std::size_t k = 0; k < va.size(); ++k) worst = std::max(worst, std::abs(va[k] - vb[k]));
  EXPECT_LE(worst, c.tolerance * range) << "range " << range;
  EXPECT_GT(test::correlation(va, vb), 0.99);
}

INSTANTIATE_TEST_SUITE_P(FieldOps, FieldOpContract, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& info) { return info.param.name; });

const char* const kOwnedTypes[] = {
    "Subtract",  "Min",     "Max",      "Blend",      "Remap",         "Clamp", "Normalize", "Curve", "Power",
    "Terrace",   "Invert",  "Abs",      "SmoothStep", "Threshold",     "Blur",  "Warp",      "Slope", "Aspect",
    "Curvature", "Normals", "BandMask", "ColorRamp",  "RadialFalloff", "Cone",  "Resample"};

TEST(FieldOpContract, EveryOwnedNodeIsCovered) {
  std::vector<std::string> covered;
  for (const auto& c : cases()) covered.push_back(c.type);
  for (const char* type : kOwnedTypes) {
    ASSERT_NE(NodeRegistry::instance().find(type), nullptr) << type;
    EXPECT_NE(std::find(covered.begin(), covered.end(), type), covered.end()) << type;
  }
}

TEST(FieldOpContract, EveryParameterAndInputChangesTheCacheKey) {
  const Domain d = Domain::from_extent({0, 0}, {1024, 1024}, {64, 64});
  for (const char* type : kOwnedTypes) {
    SCOPED_TRACE(type);
    expect_every_param_changes_key(type, d);
    expect_every_input_changes_key(type, d);
  }
}

TEST(FieldOpContract, DeclarationsAreDocumented) {
  for (const char* type : kOwnedTypes) {
    const NodeType* t = NodeRegistry::instance().find(type);
    ASSERT_NE(t, nullptr);
    EXPECT_FALSE(t->description.empty()) << type;
    for (const auto& p : t->inputs) EXPECT_FALSE(p.description.empty()) << type << "." << p.name;
    for (const auto& p : t->outputs) EXPECT_FALSE(p.description.empty()) << type << "." << p.name;
    for (const auto& p : t->params) EXPECT_FALSE(p.description.empty()) << type << "." << p.name;
  }
}

}  // namespace
}  // namespace orogen
