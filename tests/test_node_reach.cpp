// Reach (graph/node_type.h): every registered node type declares it, and every non-global one keeps it: an
// evaluation on a sub-domain expanded by its halo reproduces the full-domain result inside the sub-domain
// bit for bit. Generic over the registry, with inputs generated per port and every enum choice tried.
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "evaluator/run_node.h"
#include "field_ops_fixtures.h"
#include "graph/curves.h"
#include "graph/heightfield.h"
#include "graph/polygon_map.h"
#include "graph/image.h"
#include "graph/report.h"
#include "graph/registry.h"
#include "support/test_paths.h"

namespace orogen {
namespace {

// Smooth terrain plus per-sample detail hashed from the global lattice index, so every sample differs
// from its neighbours and a halo that is too small shows.
double detail(const Domain& d, int i, int j) { return test::hash01(d.first.x + i, d.first.y + j) - 0.5; }

// Curves and polygon maps in fixed world coordinates (the same for every domain) over the region the test's
// domains cover: x in about [-1300, 0], y in about [500, 1600].
PortValue fixed_curves() {
  static const CurvesPtr curves = [] {
    auto c = std::make_shared<Curves>();
    for (int k = 0; k < 4; ++k) {
      Curve curve;
      for (int i = 0; i <= 40; ++i) {
        const double t = i / 40.0;
        curve.points.emplace_back(static_cast<float>(-1400.0 + 1500.0 * t),
                                  static_cast<float>(450.0 + 300.0 * k + 120.0 * std::sin(7.0 * t + k)),
                                  static_cast<float>(50.0 * (1.0 - t) + 3.0 * k));
        curve.width.push_back(static_cast<float>(6.0 + 4.0 * k));
      }
      c->curves.push_back(std::move(curve));
    }
    return c;
  }();
  return PortValue(curves);
}

PortValue fixed_polygon_map() {
  static const PolygonMapPtr map = run_node("VoronoiIsland", Domain::from_extent({0, 0}, {1, 1}, {2, 2}),
                                            {{"min_corner", glm::dvec2(-1500, 300)},
                                             {"size", glm::dvec2(1700, 1500)},
                                             {"cells", std::int64_t{300}},
                                             {"shape_scale", 1.0}})
                                       .get<PolygonMap>(0);
  return PortValue(map);
}

PortValue input_for(const PortDecl& port, const Domain& d) {
  if (port.type == PortType::Curves) return fixed_curves();
  if (port.type == PortType::PolygonMap) return fixed_polygon_map();
  if (port.type == PortType::Image) {  // 12 channels (monthly climate images, layer weights): smooth plus detail
    auto img = std::make_shared<Image>(d, 12);
    for (int j = 0; j < d.height(); ++j)
      for (int i = 0; i < d.width(); ++i)
        for (int c = 0; c < 12; ++c)
          img->pixel(i, j)[c] = static_cast<float>(0.5 + 0.3 * std::sin(d.x(i) / (150.0 + 10 * c) + d.y(j) / 210.0) +
                                                   0.1 * detail(d, i, j));
    return PortValue(ImagePtr(img));
  }
  auto h = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) {
      const double x = d.x(i), y = d.y(j), n = detail(d, i, j);
      double v;
      if (port.name == "mask" || port.name == "roughness" || port.name == "amplitude")
        v = 0.5 + 0.4 * std::sin(x / 170.0 + y / 230.0) + 0.1 * n;  // 0..1
      else if (port.name == "dx" || port.name == "dy" || port.name == "warp_x" || port.name == "warp_y" ||
               port.name == "distance_offset")
        v = 30.0 * std::sin((port.name.back() == 'y' ? x : y) / 140.0) + 5.0 * n;  // metres of displacement
      else
        v = test::rolling_hills(x, y) + 8.0 * n;  // heights in metres
      h->at(i, j) = static_cast<float>(v);
    }
  return PortValue(HeightfieldPtr(h));
}

struct Case {
  const NodeType* type;
  std::map<std::string, ParamValue> params;
  std::string label;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.type->name << " (" << c.label << ")"; }

// A small heightfield file for ReadHeightfield, written once.
std::string height_file() {
  static const std::string path = [] {
    const auto dir = test::scratch_dir("reach-input");
    const Domain d = Domain::from_extent({0, 0}, {1000, 800}, {41, 33});
    PortDecl port{"in", PortType::Heightfield, "", false};
    OutputPolicy policy;
    policy.output_dir = dir;
    run_node("WriteHeightfield", d, {{"path", std::string("h.exr")}}, {{"in", input_for(port, d)}}, policy);
    return (dir / "h.exr").string();
  }();
  return path;
}

// Defaults, every other choice of each enum parameter, and cases for the other branches of an algorithm.
std::vector<Case> cases_for(const NodeType& t) {
  std::vector<Case> out{{&t, {}, "defaults"}};
  if (t.name == "ReadHeightfield") {
    out[0].params = {{"path", height_file()}};
    out.push_back({&t,
                   {{"path", height_file()}, {"origin", glm::dvec2(-1000, 600)}, {"size", glm::dvec2(900, 700)}},
                   "explicit rectangle"});
  }
  for (const auto& p : t.params)
    for (const auto& c : p.choices)
      if (c != std::get<std::string>(p.default_value)) out.push_back({&t, {{p.name, c}}, p.name + "=" + c});
  if (t.name == "Blur") {  // beyond kDirectMaxSigma samples: the decimated evaluation
    out.push_back({&t, {{"sigma", 230.0}}, "sigma=230"});
    out.push_back({&t, {{"sigma", 170.0}, {"edges", std::string("mirror")}}, "sigma=170 mirror"});
  }
  return out;
}

std::vector<ParamValue> effective(const NodeType& t, const std::map<std::string, ParamValue>& given) {
  std::vector<ParamValue> v;
  for (const auto& p : t.params) {
    const auto it = given.find(p.name);
    v.push_back(it != given.end() ? it->second : p.default_value);
  }
  return v;
}

// The w x h samples at (i0, j0) of output `k`, as raw bits (all channels of images).
std::vector<float> crop(const PortValue& v, int i0, int j0, int w, int h) {
  std::vector<float> out;
  if (const auto* f = std::get_if<HeightfieldPtr>(&v)) {
    for (int j = j0; j < j0 + h; ++j)
      for (int i = i0; i < i0 + w; ++i) out.push_back((*f)->at(i, j));
  } else if (const auto* img = std::get_if<ImagePtr>(&v)) {
    for (int j = j0; j < j0 + h; ++j)
      for (int i = i0; i < i0 + w; ++i)
        for (int c = 0; c < (*img)->channels; ++c) out.push_back((*img)->pixel(i, j)[c]);
  } else if (const auto* rep = std::get_if<ReportPtr>(&v)) {
    // A report describes the node's settings, not samples (Biomes' table): it must not change either.
    for (char ch : (*rep)->json) out.push_back(static_cast<float>(ch));
  } else {
    ADD_FAILURE() << "a non-global node with an output that is neither a field nor an image";
  }
  return out;
}

NodeRun run_on(const Case& c, const Domain& d) {
  std::map<std::string, PortValue> inputs;
  for (const auto& port : c.type->inputs) inputs[port.name] = input_for(port, d);
  return run_node(c.type->name, d, c.params, inputs);
}

// The full domain, the sub-domain and its expansion by `halo`: anisotropic spacing, an odd origin, and a
// margin beyond the expansion so the full domain's own edges are out of reach.
struct Domains {
  Domain full, sub, expanded;
  glm::ivec2 sub_at;  // the sub-domain's first sample in the full domain
  glm::ivec2 sub_in_expanded;
};

Domains domains_for(glm::ivec2 halo) {
  const glm::ivec2 size{40, 30}, margin{9, 7};
  Domains d;
  const glm::ivec2 res = size + 2 * (halo + margin);
  d.full = Domain::from_extent({-1234.5, 567.25}, {10.0 * (res.x - 1), 8.0 * (res.y - 1)}, res);
  d.sub_at = halo + margin;
  d.sub_in_expanded = halo;
  d.sub = d.full.subdomain(d.sub_at.x, d.sub_at.y, size.x, size.y);
  d.expanded = d.full.subdomain(margin.x, margin.y, size.x + 2 * halo.x, size.y + 2 * halo.y);
  return d;
}

TEST(NodeReach, EveryNodeTypeDeclaresItsReach) {
  for (const NodeType* t : NodeRegistry::instance().all()) {
    for (const auto& c : cases_for(*t)) {
      EXPECT_NE(t->reach_for(effective(*t, c.params)).kind, ReachKind::Undeclared)
          << t->name << " (" << c.label << ") declares no reach: call b.reach_pointwise(), reach_local(metres, "
          << "samples), reach_global() or reach(fn, summary) in its declaration";
    }
    EXPECT_NE(t->reach_text(), "undeclared") << t->name;
  }
}

TEST(NodeReach, WritersMeshesAndNormalizationsAreGlobal) {
  for (const char* name : {"Normalize", "Warp", "Resample", "HeightfieldToMesh", "WriteHeightfield", "WriteImage",
                           "WriteMesh", "WritePoints"}) {
    const NodeType* t = NodeRegistry::instance().find(name);
    ASSERT_NE(t, nullptr) << name;
    EXPECT_EQ(t->reach_for(effective(*t, {})).kind, ReachKind::Global) << name;
  }
  const NodeType* curve = NodeRegistry::instance().find("Curve");
  EXPECT_EQ(curve->reach_for(effective(*curve, {{"range", std::string("field")}})).kind, ReachKind::Global);
  EXPECT_EQ(curve->reach_for(effective(*curve, {})).kind, ReachKind::Pointwise);
}

TEST(NodeReach, HaloFromMetresAndSamples) {
  EXPECT_EQ(Reach::pointwise().halo({10, 8}), glm::ivec2(0, 0));
  EXPECT_EQ(Reach::local(0, 1).halo({10, 8}), glm::ivec2(1, 1));
  EXPECT_EQ(Reach::local(40, 2).halo({10, 8}), glm::ivec2(6, 7));  // 4 + 2, ceil(5) + 2
  EXPECT_EQ(Reach::global().halo({10, 8}), glm::ivec2(-1, -1));
  EXPECT_EQ(Reach::local(40, 2).describe(), "local: 40 m + 2 samples");
  EXPECT_EQ(Reach::local(0, 1).describe(), "local: 1 sample");
}

class ReachContract : public ::testing::TestWithParam<Case> {};

TEST_P(ReachContract, ExpandedSubDomainReproducesTheFullDomainBitForBit) {
  const Case& c = GetParam();
  const Reach reach = c.type->reach_for(effective(*c.type, c.params));
  if (reach.is_global()) GTEST_SKIP() << "global";
  // The halo is measured on the test lattice (10 m x 8 m).
  const glm::ivec2 halo = reach.halo({10.0, 8.0});
  const Domains d = domains_for(halo);
  ASSERT_EQ(d.full.spacing, glm::dvec2(10.0, 8.0));
  const NodeRun full = run_on(c, d.full);
  const NodeRun part = run_on(c, d.expanded);
  ASSERT_EQ(full.outputs.size(), part.outputs.size());
  for (std::size_t k = 0; k < full.outputs.size(); ++k) {
    const auto a = crop(full.outputs[k], d.sub_at.x, d.sub_at.y, d.sub.width(), d.sub.height());
    const auto b = crop(part.outputs[k], d.sub_in_expanded.x, d.sub_in_expanded.y, d.sub.width(), d.sub.height());
    ASSERT_FALSE(a.empty());
    EXPECT_TRUE(test::bit_identical(a, b))
        << c.type->name << " (" << c.label << "), reach " << reach.describe() << ", output " << c.type->outputs[k].name;
  }
}

std::vector<Case> all_cases() {
  std::vector<Case> out;
  for (const NodeType* t : NodeRegistry::instance().all())
    for (auto& c : cases_for(*t)) out.push_back(std::move(c));
  return out;
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  std::string s = info.param.type->name + "_" + info.param.label;
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(Registry, ReachContract, ::testing::ValuesIn(all_cases()), case_name);

// The contract can fail: a local node evaluated without its halo differs at the sub-domain's border.
TEST(NodeReach, TooSmallAHaloShows) {
  const Case slope{NodeRegistry::instance().find("Slope"), {}, "defaults"};
  const Case blur{NodeRegistry::instance().find("Blur"), {{"sigma", 230.0}}, "wide"};
  for (const Case& c : {slope, blur}) {
    const Reach reach = c.type->reach_for(effective(*c.type, c.params));
    const Domains d = domains_for(reach.halo({10.0, 8.0}));
    const auto a = crop(run_on(c, d.full).outputs[0], d.sub_at.x, d.sub_at.y, d.sub.width(), d.sub.height());
    const auto b = crop(run_on(c, d.sub).outputs[0], 0, 0, d.sub.width(), d.sub.height());
    EXPECT_FALSE(test::bit_identical(a, b)) << c.type->name;
  }
}

}  // namespace
}  // namespace orogen
