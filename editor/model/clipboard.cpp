#include "editor/model/clipboard.h"

#include <algorithm>
#include <cctype>
#include <limits>
#include <map>
#include <set>

#include "editor/model/document.h"
#include "graph/graph_file.h"

namespace orogen::editor {

std::string copy_fragment(const Graph& graph, const std::vector<std::string>& ids) {
  const std::set<std::string> wanted(ids.begin(), ids.end());
  Graph fragment;
  fragment.domain = graph.domain;
  for (const auto& node : graph.nodes()) {
    if (!wanted.count(node.id)) continue;
    Node& copy = fragment.add_node(*node.type, node.id);
    copy.params = node.params;
    if (auto it = graph.editor.positions.find(node.id); it != graph.editor.positions.end())
      fragment.editor.positions[node.id] = it->second;
  }
  for (const auto& node : graph.nodes()) {
    if (!wanted.count(node.id)) continue;
    for (const auto& [port, source] : node.inputs)
      if (wanted.count(source.node)) fragment.connect(source, node.id, port);
  }
  return serialize_graph(fragment);
}

namespace {

// "fbm2" -> "fbm": pasted copies are numbered from the original's name.
std::string strip_number(const std::string& id) {
  auto end = id.size();
  while (end > 1 && std::isdigit(static_cast<unsigned char>(id[end - 1]))) --end;
  return id.substr(0, end);
}

}  // namespace

std::vector<std::string> paste_fragment(Graph& graph, std::string_view text, std::optional<glm::dvec2> at) {
  LoadOptions options;
  options.drop_dangling_links = true;
  options.allow_unconnected_inputs = true;
  auto loaded = parse_graph(text, options);
  if (!loaded.ok()) throw DocumentError("the clipboard does not hold a graph fragment:\n" + loaded.error_text());
  const Graph& fragment = *loaded.graph;

  // New ids: keep the fragment's where free, else number them, avoiding every id in either graph.
  std::set<std::string> taken;
  for (const auto& n : graph.nodes()) taken.insert(n.id);
  for (const auto& n : fragment.nodes()) taken.insert(n.id);
  std::map<std::string, std::string> new_id;
  for (const auto& n : fragment.nodes()) {
    if (!graph.find(n.id)) {
      new_id[n.id] = n.id;
      continue;
    }
    const auto base = strip_number(n.id);
    for (int k = 2;; ++k)
      if (auto candidate = base + std::to_string(k); !taken.count(candidate)) {
        taken.insert(candidate);
        new_id[n.id] = candidate;
        break;
      }
  }

  // Offset: the top-left of the positioned nodes goes to `at`.
  glm::dvec2 offset{0.0, 0.0};
  if (at) {
    glm::dvec2 lo{std::numeric_limits<double>::max()};
    for (const auto& [id, p] : fragment.editor.positions) lo = glm::min(lo, p);
    offset = fragment.editor.positions.empty() ? glm::dvec2(0.0) : *at - lo;
  }

  std::vector<std::string> ids;
  Graph result = graph;  // all or nothing
  int unplaced = 0;
  for (const auto& n : fragment.nodes()) {
    const auto& id = new_id.at(n.id);
    Node& added = result.add_node(*n.type, id);
    added.params = n.params;
    if (auto it = fragment.editor.positions.find(n.id); it != fragment.editor.positions.end())
      result.editor.positions[id] = it->second + offset;
    else if (at)
      result.editor.positions[id] = *at + glm::dvec2(0.0, 120.0 * unplaced++);
    ids.push_back(id);
  }
  for (const auto& n : fragment.nodes())
    for (const auto& [port, source] : n.inputs)
      result.connect(PortRef{new_id.at(source.node), source.port}, new_id.at(n.id), port);
  graph = std::move(result);
  return ids;
}

}  // namespace orogen::editor
