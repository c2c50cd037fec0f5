// Cache keys of every registered node type: every parameter and every input changes the key, and nothing else
// does (tests/support/key_checks.h). Generated from the registry, so a new node type is covered without
// touching this file: a node that forgets a parameter in its key would serve stale results from the cache.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "graph/domain.h"
#include "graph/node_type.h"
#include "graph/registry.h"
#include "support/key_checks.h"
#include "support/registered_types.h"

namespace orogen {
namespace {

class EveryNodeKey : public testing::TestWithParam<std::string> {};

TEST_P(EveryNodeKey, EveryParameterChangesTheKeyAndNothingElseDoes) {
  expect_every_param_changes_key(GetParam(), Domain::from_extent({-300.0, 200.0}, {480.0, 384.0}, {16, 13}));
}

TEST_P(EveryNodeKey, EveryInputChangesTheKey) {
  expect_every_input_changes_key(GetParam(), Domain::from_extent({-300.0, 200.0}, {480.0, 384.0}, {16, 13}));
}

INSTANTIATE_TEST_SUITE_P(Registry, EveryNodeKey, testing::ValuesIn(test::registered_type_names()),
                         test::type_test_name);

TEST(EveryNodeKey, CoversTheWholeRegistry) {
  // The seven node families of the second round and the foundation: far more than a handful of types. A
  // registry that came up empty (a link order that dropped the self-registrations) would make every
  // parameterised test above vanish silently.
  EXPECT_GE(test::registered_type_names().size(), 80u);
}

}  // namespace
}  // namespace orogen
