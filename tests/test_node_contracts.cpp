// The node contracts of testing/contracts.h that the other registry-wide tests do not cover, on every
// registered type: a consistent, documented declaration, and the same result for any thread count. (Cache
// keys: test_node_keys.cpp; reach: test_node_reach.cpp; the same checks `orogen test-node` runs.)
#include <gtest/gtest.h>

#include <algorithm>
#include <thread>

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

TEST_P(EveryNodeContract, SameResultForAnyThreadCount) {
  const NodeType& t = type_of(GetParam());
  const int threads = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 2u, 4u));
  const Domain d = Domain::from_extent({-1234.5, 567.25}, {630.0, 376.0}, {64, 48});
  for (const auto& c : contracts::param_cases(t))
    for (const auto& f : contracts::check_threads(t, c, d, threads).failures) ADD_FAILURE() << f;
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
