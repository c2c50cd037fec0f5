#include "editor/model/node_layout.h"

#include <algorithm>
#include <cctype>
#include <limits>

namespace orogen::editor {

const PinLayout* NodeLayout::find_pin(const std::string& port, bool output) const {
  for (const auto& p : output ? outputs : inputs)
    if (p.pin.port == port) return &p;
  return nullptr;
}

std::string node_title(const Node& node) {
  std::string type_lower, id_stem;
  for (char c : node.type->name) type_lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  id_stem = node.id;
  while (!id_stem.empty() && std::isdigit(static_cast<unsigned char>(id_stem.back()))) id_stem.pop_back();
  if (id_stem == type_lower) return node.id;
  return node.id + " : " + node.type->name;
}

NodeLayout layout_node(const Node& node, glm::dvec2 position) {
  using M = NodeMetrics;
  const NodeType& type = *node.type;
  const auto text_width = [](std::size_t chars) { return static_cast<double>(chars) * M::kGlyphWidth; };

  double width = text_width(node_title(node).size()) + 2 * M::kPadding + 8.0;
  const std::size_t rows = std::max<std::size_t>({type.inputs.size(), type.outputs.size(), 1});
  for (std::size_t r = 0; r < rows; ++r) {
    const std::size_t in = r < type.inputs.size() ? type.inputs[r].name.size() : 0;
    const std::size_t out = r < type.outputs.size() ? type.outputs[r].name.size() : 0;
    width = std::max(width, text_width(in + out) + 4 * M::kPadding);
  }
  width = std::clamp(width, M::kMinWidth, M::kMaxWidth);
  const double height = M::kTitleHeight + static_cast<double>(rows) * M::kRowHeight + M::kStatusHeight + 4.0;

  NodeLayout layout;
  layout.id = node.id;
  layout.rect = {position, position + glm::dvec2(width, height)};
  layout.title = {position, position + glm::dvec2(width, M::kTitleHeight)};
  layout.status = {{position.x, layout.rect.max.y - M::kStatusHeight}, layout.rect.max};
  const auto row_y = [&](std::size_t r) {
    return position.y + M::kTitleHeight + 2.0 + (static_cast<double>(r) + 0.5) * M::kRowHeight;
  };
  for (std::size_t r = 0; r < type.inputs.size(); ++r)
    layout.inputs.push_back({{node.id, type.inputs[r].name, false}, type.inputs[r].type, {position.x, row_y(r)}});
  for (std::size_t r = 0; r < type.outputs.size(); ++r)
    layout.outputs.push_back(
        {{node.id, type.outputs[r].name, true}, type.outputs[r].type, {position.x + width, row_y(r)}});
  return layout;
}

std::map<std::string, glm::dvec2> auto_positions(const Graph& graph) {
  constexpr double kColumn = 260.0, kRow = 150.0;
  std::map<std::string, int> depth;
  std::vector<std::string> order;
  try {
    order = graph.topological_order();
  } catch (const GraphError&) {
    for (const auto& n : graph.nodes()) order.push_back(n.id);
  }
  for (const auto& id : order) {
    int d = 0;
    for (const auto& [port, src] : graph.at(id).inputs)
      if (auto it = depth.find(src.node); it != depth.end()) d = std::max(d, it->second + 1);
    depth[id] = d;
  }
  // Start below whatever is already placed.
  double top = 0.0;
  for (const auto& [id, p] : graph.editor.positions) top = std::max(top, p.y + kRow);
  std::map<int, int> rows;
  std::map<std::string, glm::dvec2> out;
  for (const auto& n : graph.nodes()) {
    if (graph.editor.positions.count(n.id)) continue;
    const int d = depth.count(n.id) ? depth[n.id] : 0;
    out[n.id] = {d * kColumn, top + rows[d]++ * kRow};
  }
  return out;
}

void place_unpositioned_nodes(Graph& graph) {
  for (const auto& [id, p] : auto_positions(graph)) graph.editor.positions[id] = p;
}

void CanvasLayout::build(const Graph& graph) {
  nodes_.clear();
  index_.clear();
  std::map<std::string, glm::dvec2> fallback;
  if (graph.editor.positions.size() < graph.nodes().size()) fallback = auto_positions(graph);
  for (const auto& node : graph.nodes()) {
    auto it = graph.editor.positions.find(node.id);
    const glm::dvec2 pos = it != graph.editor.positions.end() ? it->second : fallback[node.id];
    index_[node.id] = nodes_.size();
    nodes_.push_back(layout_node(node, pos));
  }
}

const NodeLayout* CanvasLayout::find(const std::string& id) const {
  auto it = index_.find(id);
  return it == index_.end() ? nullptr : &nodes_[it->second];
}

std::optional<std::string> CanvasLayout::node_at(glm::dvec2 world) const {
  for (auto it = nodes_.rbegin(); it != nodes_.rend(); ++it)
    if (it->rect.contains(world)) return it->id;
  return std::nullopt;
}

std::optional<PinLayout> CanvasLayout::pin_at(glm::dvec2 world, double radius) const {
  std::optional<PinLayout> best;
  double best_d2 = radius * radius;
  for (const auto& n : nodes_) {
    if (!n.rect.expanded(radius).contains(world)) continue;
    for (const auto* pins : {&n.inputs, &n.outputs})
      for (const auto& p : *pins) {
        const glm::dvec2 d = p.position - world;
        const double d2 = d.x * d.x + d.y * d.y;
        if (d2 <= best_d2) {
          best_d2 = d2;
          best = p;
        }
      }
  }
  return best;
}

std::vector<std::string> CanvasLayout::nodes_in(const Rect& world) const {
  std::vector<std::string> out;
  for (const auto& n : nodes_)
    if (n.rect.overlaps(world)) out.push_back(n.id);
  return out;
}

std::optional<Rect> CanvasLayout::bounds(const std::vector<std::string>& ids) const {
  std::optional<Rect> box;
  auto add = [&](const NodeLayout& n) { box = box ? box->united(n.rect) : n.rect; };
  if (ids.empty()) {
    for (const auto& n : nodes_) add(n);
  } else {
    for (const auto& id : ids)
      if (const auto* n = find(id)) add(*n);
  }
  return box;
}

}  // namespace orogen::editor
