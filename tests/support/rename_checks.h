#pragma once
// A graph-format rename table must match the registry: every old name gone, every new one declared.
#include <gtest/gtest.h>

#include <vector>

#include "graph/graph_migrations.h"
#include "graph/registry.h"

namespace orogen::test {

inline void expect_renames_match_registry(const std::vector<NodeRenamesV1>& renames) {
  for (const auto& r : renames) {
    const NodeType* t = NodeRegistry::instance().find(r.type);
    ASSERT_NE(t, nullptr) << r.type;
    for (const auto& [from, to] : r.inputs) {
      EXPECT_EQ(t->find_input(from), nullptr) << r.type << "." << from;
      EXPECT_NE(t->find_input(to), nullptr) << r.type << "." << to;
    }
    for (const auto& [from, to] : r.outputs) {
      EXPECT_EQ(t->find_output(from), nullptr) << r.type << "." << from;
      EXPECT_NE(t->find_output(to), nullptr) << r.type << "." << to;
    }
    for (const auto& [from, to] : r.params) {
      EXPECT_EQ(t->find_param(from), nullptr) << r.type << "." << from;
      EXPECT_NE(t->find_param(to), nullptr) << r.type << "." << to;
    }
  }
}

}  // namespace orogen::test
