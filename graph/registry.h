#pragma once
// The registry of node types: the single source for the file loader, the editor's palette and inspector,
// `orogen nodes` and the generated node reference.
#include <memory>
#include <shared_mutex>
#include <string>
#include <string_view>
#include <vector>

#include "graph/node_type.h"

namespace orogen {

class NodeRegistry {
 public:
  static NodeRegistry& instance();

  // Adds a type after check_declaration; throws std::logic_error on an invalid or duplicate declaration.
  // Safe while other threads read the registry (the editor loads node libraries while previews run).
  const NodeType& add(NodeType type);
  const NodeType* find(std::string_view name) const;
  // All types sorted by category, then name.
  std::vector<const NodeType*> all() const;
  // The registered name closest to `name` (edit distance, case-insensitive), or "" if none is close.
  std::string closest(std::string_view name) const;

  // While a node library is being opened, its OROGEN_NODE registrations are collected here instead of added,
  // so the loader can check them all before any becomes visible (graph/node_library.cpp). Not reentrant.
  struct Staging {
    std::vector<NodeType> types;
    std::vector<std::string> errors;  // declarations that threw
  };
  void set_staging(Staging* staging) { staging_ = staging; }
  Staging* staging() const { return staging_; }

 private:
  mutable std::shared_mutex mutex_;
  std::vector<std::unique_ptr<NodeType>> types_;
  Staging* staging_ = nullptr;
};

// Registers a type at static-initialisation time; see OROGEN_NODE.
struct NodeRegistration {
  NodeRegistration(const char* name, void (*declare)(NodeBuilder&));
};

// Case-insensitive Levenshtein distance (used for "did you mean" suggestions).
std::size_t edit_distance(std::string_view a, std::string_view b);

}  // namespace orogen

// Declares and registers a node type in one line: OROGEN_NODE(Name) { b.category(...); ... }
// Node sources are linked as an object library so no registration is dropped by the linker.
#define OROGEN_NODE(TypeName)                                                                                    \
  static void orogen_declare_##TypeName(::orogen::NodeBuilder& b);                                               \
  static const ::orogen::NodeRegistration orogen_registration_##TypeName{#TypeName, &orogen_declare_##TypeName}; \
  static void orogen_declare_##TypeName([[maybe_unused]] ::orogen::NodeBuilder& b)
