#include "support/key_checks.h"

#include <gtest/gtest.h>

#include "graph/registry.h"
#include "testing/contracts.h"

// The checks themselves are the node contracts' (testing/contracts.h), shared with `orogen test-node` and the
// testing kit of node libraries; here they report through GoogleTest.
namespace orogen::test {
namespace {

template <class Check>
void expect_none(const std::string& type_name, const Domain& d, Check check) {
  const NodeType* type = NodeRegistry::instance().find(type_name);
  if (!type) {
    ADD_FAILURE() << "no registered node type '" << type_name << "'";
    return;
  }
  for (const auto& failure : check(*type, d)) ADD_FAILURE() << failure;
}

}  // namespace

void expect_every_param_changes_key(const std::string& type_name, const Domain& d) {
  expect_none(type_name, d, contracts::param_key_failures);
}

void expect_every_input_changes_key(const std::string& type_name, const Domain& d) {
  expect_none(type_name, d, contracts::input_key_failures);
}

}  // namespace orogen::test
