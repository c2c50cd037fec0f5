#include "editor/model/exposed_params.h"

#include <set>

#include <nlohmann/json.hpp>

#include "editor/model/interface_reread.h"
#include "graph/graph_file.h"
#include "graph/subgraph.h"

namespace orogen::editor {

using nlohmann::json;

std::string exposed_as(const Graph& graph, const std::string& node, const std::string& param) {
  if (!graph.interface) return {};
  for (const auto& p : graph.interface->params)
    for (const auto& t : p.targets)
      if (t.node == node && t.name == param) return p.decl.name;
  return {};
}

std::string set_exposed(Document& document, const std::string& node, const std::string& param, bool exposed) {
  const Graph& graph = document.graph();
  if (!graph.interface)
    throw DocumentError("only a subgraph asset exposes parameters: enter an instance or open its asset file");
  const Node& n = graph.at(node);
  const ParamDecl* decl = n.type->find_param(param);
  if (!decl) throw DocumentError("node '" + node + "' has no parameter '" + param + "'");
  if (!exposed_as(graph, node, param).empty() == exposed) return exposed ? exposed_as(graph, node, param) : "";

  json in = json::parse(graph.interface->json_text);
  json& params = in["params"];
  if (!params.is_array()) params = json::array();
  const std::string target = node + "." + param;
  std::string name;
  if (exposed) {
    std::set<std::string> taken;
    for (const auto& p : params)
      if (p.contains("name") && p["name"].is_string()) taken.insert(p["name"].get<std::string>());
    name = taken.count(param) ? node + "_" + param : param;
    for (int k = 2; taken.count(name); ++k) name = node + "_" + param + std::to_string(k);
    for (char& c : name)
      if (c == '-') c = '_';
    // The declaration, default and range come from the inner parameter (graph_file.cpp, read_exposed_param).
    params.push_back({{"name", name}, {"type", std::string(to_string(decl->type))}, {"to", target}});
  } else {
    json kept = json::array();
    for (auto& p : params) {
      json& to = p["to"];
      if (to.is_string() && to.get<std::string>() == target) continue;
      if (to.is_array()) {
        json rest = json::array();
        for (const auto& t : to)
          if (!(t.is_string() && t.get<std::string>() == target)) rest.push_back(t);
        if (rest.empty()) continue;
        to = rest.size() == 1 ? rest.front() : rest;
      }
      kept.push_back(p);
    }
    params = kept;
  }
  // A changed interface is a new asset version.
  in["asset_version"] =
      (in.contains("asset_version") && in["asset_version"].is_number_integer() ? in["asset_version"].get<int>() : 1) +
      1;

  // The interface read back from the file form, so that it is whole (targets, declarations), not just text.
  const LoadResult reread = reread_with_interface(graph, in, /*keep_partial=*/false);
  if (!reread.graph || !reread.graph->interface)
    throw DocumentError("cannot " + std::string(exposed ? "expose " : "hide ") + target + ":\n" + reread.error_text());
  for (const auto& d : reread.diagnostics)
    if (d.path.rfind("/interface", 0) == 0)
      throw DocumentError("cannot " + std::string(exposed ? "expose " : "hide ") + target + ": " + d.str());
  const auto interface = reread.graph->interface;
  document.edit((exposed ? "Expose " : "Hide ") + target, [&](Graph& g) { g.interface = interface; });
  return name;
}

}  // namespace orogen::editor
