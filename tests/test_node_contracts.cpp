// `orogen test-node` passes on every built-in node type: each contract of testing/contracts.h runs once per
// registered type (no process launches), here (declaration, threads) or in the wider sweeps of the same
// functions (cache key: test_node_keys.cpp, reach: test_node_reach.cpp, extremes: test_node_extremes.cpp).
#include <gtest/gtest.h>

#include <algorithm>

#include "graph/registry.h"
#include "support/registered_types.h"
#include "testing/contracts.h"

namespace orogen {
namespace {

class EveryNodeContract : public testing::TestWithParam<std::string> {};

const NodeType& type_of(const std::string& name) { return *NodeRegistry::instance().find(name); }

TEST_P(EveryNodeContract, DeclarationIsDocumentedAndConsistent) {
  for (const auto& f : contracts::check_declaration_contract(type_of(GetParam())).failures) ADD_FAILURE() << f;
}

TEST_P(EveryNodeContract, ThreadCountDoesNotChangeTheResult) {
  const NodeType& t = type_of(GetParam());
  ASSERT_TRUE(t.library.empty()) << "a built-in type";
  const auto rows = contracts::check_node_contracts(t, contracts::kThreadsContract);
  ASSERT_EQ(rows.size(), 1u);
  EXPECT_NE(rows[0].status, contracts::Status::Failed) << rows[0].note;
  for (const auto& f : rows[0].failures) ADD_FAILURE() << f;
}

INSTANTIATE_TEST_SUITE_P(Registry, EveryNodeContract, testing::ValuesIn(test::registered_type_names()),
                         test::type_test_name);

// What `orogen test-node` prints: the five contracts, in order, all passing on a correct node.
TEST(NodeContracts, TestNodeRunsTheFiveContractsInOrder) {
  std::vector<std::string> names;
  for (const auto& r : contracts::check_node_contracts(type_of("Slope"))) {
    names.push_back(r.contract);
    EXPECT_EQ(r.status, contracts::Status::Passed) << r.contract << ": " << r.note;
    for (const auto& f : r.failures) ADD_FAILURE() << r.contract << ": " << f;
  }
  EXPECT_EQ(names, (std::vector<std::string>{"declaration", "cache key", "reach", "threads", "extremes"}));
}

// The checks can fail: an undocumented parameter, a number without a range, a soft range beyond the hard one.
TEST(NodeContracts, AnInconsistentDeclarationIsNamed) {
  NodeType t = type_of("Slope");
  t.inputs[0].description.clear();
  NodeBuilder b(t);
  b.param_float("gain", 1.0).unit(Unit::Factor);
  b.param_float("bias", 0.0).range(-1.0, 1.0).soft_range(-2.0, 1.0).unit(Unit::Metre).description("Added");
  const auto r = contracts::check_declaration_contract(t);
  EXPECT_EQ(r.status, contracts::Status::Failed);
  auto has = [&](const std::string& part) {
    return std::any_of(r.failures.begin(), r.failures.end(),
                       [&](const std::string& f) { return f.find(part) != std::string::npos; });
  };
  EXPECT_TRUE(has("port 'in' has no description"));
  EXPECT_TRUE(has("parameter 'gain' has no description"));
  EXPECT_TRUE(has("parameter 'gain' has no hard range"));
  EXPECT_TRUE(has("parameter 'bias': its soft range starts below its hard range"));
}

}  // namespace
}  // namespace orogen
