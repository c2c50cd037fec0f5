#include "editor/model/node_layout.h"

#include "graph/subgraph.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <limits>

namespace orogen::editor {

const PinLayout* NodeLayout::find_pin(const std::string& port, bool output) const {
  for (const auto& p : output ? outputs : inputs)
    if (p.pin.port == port) return &p;
  return nullptr;
}

std::string node_title(const Node& node) {
  // An instance shows its asset: "mountains : eroded_mountain_range", not "Subgraph"; an embedded (unique)
  // one "#name", as the file names it.
  const SubgraphAsset* asset = node.type->subgraph;
  const std::string type = !asset                    ? node.type->name
                           : asset->embedded.empty() ? asset->name
                                                     : std::string(1, kEmbeddedReferencePrefix) + asset->embedded;
  std::string type_lower, id_stem;
  for (char c : type) type_lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  id_stem = node.id;
  while (!id_stem.empty() && std::isdigit(static_cast<unsigned char>(id_stem.back()))) id_stem.pop_back();
  if (id_stem == type_lower) return node.id;
  return node.id + " : " + type;
}

double monospace_width(std::string_view text) { return static_cast<double>(text.size()) * NodeMetrics::kGlyphWidth; }

NodeLayout layout_node(const Node& node, glm::dvec2 position, const TextMeasure& measure, bool thumbnails) {
  using M = NodeMetrics;
  const NodeType& type = *node.type;

  double width = measure(node_title(node)) + 2 * M::kPadding + 8.0;
  const std::size_t rows = std::max<std::size_t>({type.inputs.size(), type.outputs.size(), 1});
  for (std::size_t r = 0; r < rows; ++r) {
    const double in = r < type.inputs.size() ? measure(type.inputs[r].name) : 0.0;
    const double out = r < type.outputs.size() ? measure(type.outputs[r].name) : 0.0;
    width = std::max(width, in + out + 4 * M::kPadding);
  }
  width = std::clamp(width, M::kMinWidth, M::kMaxWidth);
  const bool picture = thumbnails && std::any_of(type.outputs.begin(), type.outputs.end(), [](const PortDecl& p) {
                         return p.type == PortType::Heightfield || p.type == PortType::Image ||
                                p.type == PortType::Points || p.type == PortType::Curves;
                       });
  const double pins_bottom = M::kTitleHeight + 2.0 + static_cast<double>(rows) * M::kRowHeight;
  const double picture_height = picture ? M::kThumbnailHeight + 6.0 : 0.0;
  const double height = pins_bottom + picture_height + M::kStatusHeight + 2.0;

  NodeLayout layout;
  layout.id = node.id;
  layout.rect = {position, position + glm::dvec2(width, height)};
  layout.title = {position, position + glm::dvec2(width, M::kTitleHeight)};
  layout.status = {{position.x, layout.rect.max.y - M::kStatusHeight}, layout.rect.max};
  if (picture)
    layout.thumbnail = Rect{{position.x + M::kPadding, position.y + pins_bottom + 2.0},
                            {position.x + width - M::kPadding, position.y + pins_bottom + 2.0 + M::kThumbnailHeight}};
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

namespace {

// Layered layout of some nodes from (0, 0): columns by longest path from the sources, each column ordered by
// the mean row of the nodes feeding it (the barycentre heuristic, which untangles most links of a
// left-to-right flow), nodes stacked by their real heights.
std::map<std::string, glm::dvec2> layered(const Graph& graph, const std::vector<std::string>& ids,
                                          const std::map<std::string, int>& depth, glm::dvec2* extent) {
  constexpr double kColumnGap = 70.0, kRowGap = 36.0;
  std::map<int, std::vector<std::string>> columns;
  for (const auto& id : ids) columns[depth.at(id)].push_back(id);
  std::map<std::string, double> row;
  for (auto& [d, column] : columns) {
    std::map<std::string, double> key;
    for (std::size_t k = 0; k < column.size(); ++k) {
      double sum = 0.0;
      int count = 0;
      for (const auto& [port, src] : graph.at(column[k]).inputs)
        if (auto it = row.find(src.node); it != row.end()) {
          sum += it->second;
          ++count;
        }
      key[column[k]] = count ? sum / count : static_cast<double>(k);
    }
    std::stable_sort(column.begin(), column.end(), [&](const auto& a, const auto& b) { return key[a] < key[b]; });
    for (std::size_t k = 0; k < column.size(); ++k) row[column[k]] = static_cast<double>(k);
  }
  std::map<std::string, glm::dvec2> out;
  double x = 0.0, height = 0.0;
  for (const auto& [d, column] : columns) {
    double y = 0.0, width = 0.0;
    for (const auto& id : column) {
      const NodeLayout l = layout_node(graph.at(id), {x, y});
      out[id] = {x, y};
      y += l.rect.size().y + kRowGap;
      width = std::max(width, l.rect.size().x);
    }
    height = std::max(height, y - kRowGap);
    x += width + kColumnGap;
  }
  *extent = {x - kColumnGap, height};
  return out;
}

}  // namespace

std::map<std::string, glm::dvec2> auto_positions(const Graph& graph) {
  constexpr double kGap = 90.0;
  std::vector<std::string> unplaced;
  for (const auto& n : graph.nodes())
    if (!graph.editor.positions.count(n.id)) unplaced.push_back(n.id);
  if (unplaced.empty()) return {};

  std::vector<std::string> order;
  try {
    order = graph.topological_order();
  } catch (const GraphError&) {
    for (const auto& n : graph.nodes()) order.push_back(n.id);
  }
  std::map<std::string, int> depth;
  for (const auto& id : order) {
    int d = 0;
    for (const auto& [port, src] : graph.at(id).inputs)
      if (auto it = depth.find(src.node); it != depth.end()) d = std::max(d, it->second + 1);
    depth[id] = d;
  }

  // Connected groups of unplaced nodes (union-find over links), in graph order.
  std::map<std::string, std::string> parent;
  for (const auto& id : unplaced) parent[id] = id;
  std::function<std::string(const std::string&)> root = [&](const std::string& id) {
    return parent[id] == id ? id : parent[id] = root(parent[id]);
  };
  for (const auto& id : unplaced)
    for (const auto& [port, src] : graph.at(id).inputs)
      if (parent.count(src.node)) parent[root(src.node)] = root(id);
  std::vector<std::vector<std::string>> groups;
  std::map<std::string, std::size_t> group_of;
  for (const auto& id : unplaced) {
    const auto r = root(id);
    if (!group_of.count(r)) {
      group_of[r] = groups.size();
      groups.emplace_back();
    }
    groups[group_of[r]].push_back(id);
  }

  // Lay out each group, then pack the groups in rows about as wide as a screen's aspect wants.
  std::vector<std::map<std::string, glm::dvec2>> placed(groups.size());
  std::vector<glm::dvec2> extent(groups.size());
  double area = 0.0, widest = 0.0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    placed[g] = layered(graph, groups[g], depth, &extent[g]);
    area += (extent[g].x + kGap) * (extent[g].y + kGap);
    widest = std::max(widest, extent[g].x);
  }
  const double row_width = std::max(widest, std::sqrt(area * 1.8));

  double top = 0.0;  // below whatever is already placed
  for (const auto& [id, p] : graph.editor.positions) top = std::max(top, p.y + 200.0);
  std::map<std::string, glm::dvec2> out;
  double x = 0.0, y = top, row_height = 0.0;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    if (x > 0.0 && x + extent[g].x > row_width) {
      x = 0.0;
      y += row_height + kGap;
      row_height = 0.0;
    }
    for (const auto& [id, p] : placed[g]) out[id] = p + glm::dvec2(x, y);
    x += extent[g].x + kGap;
    row_height = std::max(row_height, extent[g].y);
  }
  return out;
}

void place_unpositioned_nodes(Graph& graph) {
  for (const auto& [id, p] : auto_positions(graph)) graph.editor.positions[id] = p;
}

void CanvasLayout::build(const Graph& graph, const TextMeasure& measure, bool thumbnails) {
  nodes_.clear();
  index_.clear();
  std::map<std::string, glm::dvec2> fallback;
  if (graph.editor.positions.size() < graph.nodes().size()) fallback = auto_positions(graph);
  for (const auto& node : graph.nodes()) {
    auto it = graph.editor.positions.find(node.id);
    const glm::dvec2 pos = it != graph.editor.positions.end() ? it->second : fallback[node.id];
    index_[node.id] = nodes_.size();
    nodes_.push_back(layout_node(node, pos, measure, thumbnails));
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

std::size_t make_room_for_thumbnails(Graph& graph, double margin) {
  // Top to bottom: each node is pushed below every node above it that it now overlaps (the widths of the
  // real font may differ a little from the estimate: a margin on both axes).
  std::vector<const Node*> order;
  for (const auto& n : graph.nodes())
    if (graph.editor.positions.count(n.id)) order.push_back(&n);
  std::stable_sort(order.begin(), order.end(), [&](const Node* a, const Node* b) {
    const auto pa = graph.editor.positions.at(a->id), pb = graph.editor.positions.at(b->id);
    return pa.y != pb.y ? pa.y < pb.y : pa.x < pb.x;
  });
  std::vector<Rect> placed;
  std::size_t moved = 0;
  for (const Node* n : order) {
    glm::dvec2& pos = graph.editor.positions.at(n->id);
    Rect r = layout_node(*n, pos, monospace_width, true).rect;
    bool shifted = false;
    for (bool again = true; again;) {
      again = false;
      for (const Rect& p : placed) {
        const bool x_overlap = r.min.x < p.max.x + margin && p.min.x < r.max.x + margin;
        const bool y_overlap = r.min.y < p.max.y + margin && p.min.y < r.max.y + margin;
        if (x_overlap && y_overlap) {
          const double dy = p.max.y + margin - r.min.y;
          r.min.y += dy;
          r.max.y += dy;
          pos.y += dy;
          shifted = again = true;
        }
      }
    }
    if (shifted) ++moved;
    placed.push_back(r);
  }
  return moved;
}

}  // namespace orogen::editor
