#include <iostream>
#include <sstream>

#include "cli/commands.h"
#include "cli/node_reference.h"
#include <nlohmann/json.hpp>

#include "graph/graph_file.h"
#include "graph/json_util.h"
#include "graph/registry.h"
#include "graph/subgraph.h"

namespace orogen::cli {

namespace {

// One asset of the subgraph library: its name, interface and description, or why it does not load.
std::string library_asset_text(const LibraryAssetFile& entry, bool detailed) {
  std::ostringstream s;
  const AssetLoad load = load_subgraph_asset(entry.name, {});
  if (!load.asset) {
    s << "  " << entry.name << "  (does not load: " << load.error << ")\n";
    return s.str();
  }
  const SubgraphInterface& in = load.asset->interface();
  auto ports = [](const std::vector<PortDecl>& list) {
    std::string text;
    for (const auto& p : list) text += (text.empty() ? "" : ", ") + p.name + ": " + std::string(to_string(p.type));
    return text;
  };
  const NodeType& t = load.asset->type;
  s << "  " << entry.name << " (asset version " << in.asset_version << ")  in: " << ports(t.inputs)
    << "  out: " << ports(t.outputs) << "\n      " << in.description << "\n";
  if (!detailed) return s.str();
  s << "      file: " << load.asset->file.string() << "\n";
  if (!t.params.empty()) s << "      parameters:\n";
  for (const auto& p : t.params) {
    s << "        " << p.name << " : " << to_string(p.type) << " = " << param_to_json(p.default_value).dump();
    if (p.min || p.max)
      s << "  range [" << (p.min ? json_util::format_double(*p.min) : "") << ", "
        << (p.max ? json_util::format_double(*p.max) : "") << "]";
    const auto symbol = unit_symbol(p.unit);
    if (!symbol.empty()) s << " " << symbol;
    s << "\n          " << p.description << "\n";
  }
  return s.str();
}

}  // namespace

int run_nodes(const std::string& type, bool json, bool markdown) {
  if (type.empty()) {
    std::cout << (markdown ? node_reference_markdown() : json ? node_reference_json() : node_list_text());
    if (!markdown && !json) {
      // Subgraph assets of the library (graphs/library, OROGEN_LIBRARY_PATH), used as {"type": "Subgraph",
      // "asset": NAME}.
      const auto library = list_subgraph_library();
      if (!library.empty()) std::cout << "subgraph library (type Subgraph, \"asset\": NAME):\n";
      for (const auto& entry : library) std::cout << library_asset_text(entry, false);
    }
    return kExitOk;
  }
  const NodeType* t = NodeRegistry::instance().find(type);
  if (!t) {
    for (const auto& entry : list_subgraph_library())
      if (entry.name == type) {
        if (json) {
          const AssetLoad load = load_subgraph_asset(entry.name, {});
          if (!load.asset) {
            std::cerr << "error: " << load.error << "\n";
            return kExitInvalid;
          }
          std::cout << node_reference_json(&load.asset->type);
          return kExitOk;
        }
        std::cout << "subgraph library asset, used as {\"type\": \"Subgraph\", \"asset\": \"" << type << "\"}:\n"
                  << library_asset_text(entry, true);
        return kExitOk;
      }
    const auto hint = NodeRegistry::instance().closest(type);
    std::cerr << "error: unknown node type '" << type << "'" << (hint.empty() ? "" : " (did you mean '" + hint + "'?)")
              << "\n";
    return kExitInvalid;
  }
  std::cout << (json ? node_reference_json(t) : node_reference_text(*t));
  return kExitOk;
}

}  // namespace orogen::cli
