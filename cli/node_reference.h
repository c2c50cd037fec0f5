#pragma once
// The node reference generated from the registry: `orogen nodes` as text, JSON or Markdown.
#include <string>

#include "graph/node_type.h"

namespace orogen::cli {

std::string node_list_text();  // one line per type, grouped by category
std::string node_reference_text(const NodeType& type);
std::string node_reference_json(const NodeType* only = nullptr);  // every type, or just `only`
std::string node_reference_markdown();                            // docs/nodes.md

}  // namespace orogen::cli
