// Reach (graph/node_type.h): every registered node type declares it, and every non-global one keeps it: an
// evaluation on a sub-domain expanded by its halo reproduces the full-domain result inside the sub-domain
// bit for bit. Generic over the registry, with inputs generated per port and every enum choice tried. The
// check is the tile contract of testing/contracts.h, shared with `orogen test-node` and the testing kit.
#include <cctype>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "evaluator/run_node.h"
#include "graph/registry.h"
#include "support/test_paths.h"
#include "testing/contracts.h"

namespace orogen {
namespace {

using contracts::ParamCase;

struct Case {
  const NodeType* type;
  ParamCase params;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.type->name << " (" << c.params.label << ")"; }

// A small heightfield file for ReadHeightfield, written once.
std::string height_file() {
  static const std::string path = [] {
    const auto dir = test::scratch_dir("reach-input");
    const Domain d = Domain::from_extent({0, 0}, {1000, 800}, {41, 33});
    PortDecl port{"in", PortType::Heightfield, "", false};
    OutputPolicy policy;
    policy.output_dir = dir;
    run_node("WriteHeightfield", d, {{"path", std::string("h.exr")}}, {{"in", contracts::contract_input(port, d)}},
             policy);
    return (dir / "h.exr").string();
  }();
  return path;
}

// The contract's cases (defaults, every other enum choice) and cases for other branches of some algorithms.
std::vector<ParamCase> cases_for(const NodeType& t) {
  auto out = contracts::param_cases(t);
  if (t.name == "ReadHeightfield") {
    for (auto& c : out) c.params["path"] = height_file();
    out.push_back({{{"path", height_file()}, {"origin", glm::dvec2(-1000, 600)}, {"size", glm::dvec2(900, 700)}},
                   "explicit rectangle"});
  }
  if (t.name == "FlowDirection")  // without filling, a local node of one sample
    for (const char* method : {"d8", "dinf", "mfd"})
      out.push_back({{{"fill", false}, {"method", std::string(method)}}, std::string("no fill ") + method});
  if (t.name == "Blur") {  // beyond kDirectMaxSigma samples: the decimated evaluation
    out.push_back({{{"sigma", 230.0}}, "sigma=230"});
    out.push_back({{{"sigma", 170.0}, {"edges", std::string("mirror")}}, "sigma=170 mirror"});
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
  const auto r = contracts::check_reach(*c.type, c.params);
  if (r.status == contracts::Status::Skipped) GTEST_SKIP() << r.note;
  for (const auto& f : r.failures) ADD_FAILURE() << f;
}

std::vector<Case> all_cases() {
  std::vector<Case> out;
  for (const NodeType* t : NodeRegistry::instance().all())
    for (auto& c : cases_for(*t)) out.push_back({t, std::move(c)});
  return out;
}

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  std::string s = info.param.type->name + "_" + info.param.params.label;
  for (char& ch : s)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(Registry, ReachContract, ::testing::ValuesIn(all_cases()), case_name);

// The contract can fail: a local node declared with too small a reach differs at the sub-domain's border.
TEST(NodeReach, TooSmallAHaloShows) {
  struct Shrunk {
    const char* name;
    Reach declared;
    ParamCase params;
  };
  for (const auto& s : {Shrunk{"Slope", Reach::pointwise(), {{}, "defaults"}},
                        Shrunk{"Blur", Reach::local(100.0, 0), {{{"sigma", 230.0}}, "sigma=230"}}}) {
    NodeType declared_too_small = *NodeRegistry::instance().find(s.name);
    declared_too_small.reach = s.declared;
    declared_too_small.reach_fn = nullptr;
    const auto r = contracts::check_reach(declared_too_small, s.params);
    EXPECT_EQ(r.status, contracts::Status::Failed) << s.name;
    ASSERT_FALSE(r.failures.empty()) << s.name;
    EXPECT_NE(r.failures[0].find("the declared reach is too small"), std::string::npos) << r.failures[0];
  }
}

}  // namespace
}  // namespace orogen
