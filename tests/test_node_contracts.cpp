// `orogen test-node` passes on every built-in node type: the contracts of testing/contracts.h (declaration,
// cache key, reach, threads, extremes) through check_node_contracts, the function the command prints, one
// test per registered type (no process launches). The declaration check runs alone too, for its own report.
// (Wider sweeps of the same checks: test_node_keys.cpp, test_node_reach.cpp, test_node_extremes.cpp.)
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

TEST_P(EveryNodeContract, TestNodePasses) {
  const NodeType& t = type_of(GetParam());
  ASSERT_TRUE(t.library.empty()) << "a built-in type";
  // The extremes sweep is NodeExtremes' (test_node_extremes.cpp), with bounds that hold under AddressSanitizer.
  const auto rows = contracts::check_node_contracts(t, /*with_extremes=*/false);
  std::vector<std::string> names;
  for (const auto& r : rows) {
    names.push_back(r.contract);
    EXPECT_NE(r.status, contracts::Status::Failed) << "contract '" << r.contract << "' (" << r.note << ")";
    for (const auto& f : r.failures) ADD_FAILURE() << "contract '" << r.contract << "': " << f;
  }
  EXPECT_EQ(names, (std::vector<std::string>{"declaration", "cache key", "reach", "threads"}));
}

INSTANTIATE_TEST_SUITE_P(Registry, EveryNodeContract, testing::ValuesIn(test::registered_type_names()),
                         test::type_test_name);

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
