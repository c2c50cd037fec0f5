#include <iostream>

#include "cli/commands.h"
#include "cli/node_reference.h"
#include "graph/registry.h"

namespace orogen::cli {

int run_nodes(const std::string& type, bool json, bool markdown) {
  if (type.empty()) {
    std::cout << (markdown ? node_reference_markdown() : json ? node_reference_json() : node_list_text());
    return kExitOk;
  }
  const NodeType* t = NodeRegistry::instance().find(type);
  if (!t) {
    const auto hint = NodeRegistry::instance().closest(type);
    std::cerr << "error: unknown node type '" << type << "'" << (hint.empty() ? "" : " (did you mean '" + hint + "'?)")
              << "\n";
    return kExitInvalid;
  }
  std::cout << (json ? node_reference_json(t) : node_reference_text(*t));
  return kExitOk;
}

}  // namespace orogen::cli
