#pragma once
// The names of every registered node type, for registry-wide parameterised tests (a new node type is covered
// without touching them), and the test-name generator that names each instance after its type.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "graph/registry.h"

namespace orogen::test {

inline std::vector<std::string> registered_type_names() {
  std::vector<std::string> names;
  for (const NodeType* type : NodeRegistry::instance().all()) names.push_back(type->name);
  return names;
}

inline std::string type_test_name(const testing::TestParamInfo<std::string>& info) { return info.param; }

}  // namespace orogen::test
