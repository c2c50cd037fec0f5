#include "graph/graph.h"

#include <algorithm>
#include <cctype>
#include <functional>
#include <set>

#include "graph/registry.h"

namespace orogen {

bool operator==(const Node& a, const Node& b) {
  return a.id == b.id && a.type == b.type && a.asset == b.asset && a.params == b.params && a.inputs == b.inputs;
}

bool Graph::operator==(const Graph& other) const {
  return domain == other.domain && editor == other.editor && nodes_ == other.nodes_;
}

bool Graph::valid_id(const std::string& id) {
  if (id.empty() || id.size() > 128) return false;
  if (!std::isalpha(static_cast<unsigned char>(id[0])) && id[0] != '_') return false;
  return std::all_of(id.begin(), id.end(), [](unsigned char c) { return std::isalnum(c) || c == '_' || c == '-'; });
}

void Graph::reindex() {
  index_.clear();
  for (std::size_t i = 0; i < nodes_.size(); ++i) index_[nodes_[i].id] = i;
}

const Node* Graph::find(const std::string& id) const {
  const auto it = index_.find(id);
  return it == index_.end() ? nullptr : &nodes_[it->second];
}

Node* Graph::find(const std::string& id) {
  const auto it = index_.find(id);
  return it == index_.end() ? nullptr : &nodes_[it->second];
}

const Node& Graph::at(const std::string& id) const {
  if (const auto* n = find(id)) return *n;
  throw GraphError("no node '" + id + "'");
}

std::string Graph::unique_id(const std::string& base_in) const {
  std::string base;
  for (char c : base_in) base += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (!valid_id(base)) base = "node";
  if (!find(base)) return base;
  for (int k = 2;; ++k)
    if (auto id = base + std::to_string(k); !find(id)) return id;
}

Node& Graph::add_node(const std::string& type_name, std::string id) {
  const auto* type = NodeRegistry::instance().find(type_name);
  if (!type) {
    const auto hint = NodeRegistry::instance().closest(type_name);
    throw GraphError("unknown node type '" + type_name + "'" + (hint.empty() ? "" : " (did you mean '" + hint + "'?)"));
  }
  return add_node(*type, std::move(id));
}

Node& Graph::add_node(const NodeType& type, std::string id) {
  if (id.empty()) id = unique_id(type.name);
  if (!valid_id(id))
    throw GraphError("invalid node id '" + id + "': use letters, digits, '_' and '-', starting with a letter or '_'");
  if (find(id)) throw GraphError("duplicate node id '" + id + "'");
  Node n;
  n.id = std::move(id);
  n.type = &type;
  nodes_.push_back(std::move(n));
  index_[nodes_.back().id] = nodes_.size() - 1;
  return nodes_.back();
}

Node& Graph::add_expanded_node(const NodeType& type, std::string id) {
  std::size_t start = 0;
  while (true) {  // every '/'-separated part must be a valid id
    const auto slash = id.find('/', start);
    if (!valid_id(id.substr(start, slash == std::string::npos ? std::string::npos : slash - start)))
      throw GraphError("invalid expanded node id '" + id + "'");
    if (slash == std::string::npos) break;
    start = slash + 1;
  }
  if (find(id)) throw GraphError("duplicate node id '" + id + "'");
  Node n;
  n.id = std::move(id);
  n.type = &type;
  nodes_.push_back(std::move(n));
  index_[nodes_.back().id] = nodes_.size() - 1;
  return nodes_.back();
}

void Graph::remove_node(const std::string& id) {
  if (!find(id)) throw GraphError("no node '" + id + "'");
  nodes_.erase(nodes_.begin() + static_cast<std::ptrdiff_t>(index_.at(id)));
  for (auto& n : nodes_) std::erase_if(n.inputs, [&](const auto& link) { return link.second.node == id; });
  editor.positions.erase(id);
  reindex();
}

void Graph::rename_node(const std::string& id, const std::string& new_id) {
  if (id == new_id) return;
  Node* node = find(id);
  if (!node) throw GraphError("no node '" + id + "'");
  if (!valid_id(new_id)) throw GraphError("invalid node id '" + new_id + "'");
  if (find(new_id)) throw GraphError("duplicate node id '" + new_id + "'");
  node->id = new_id;
  for (auto& n : nodes_)
    for (auto& [port, src] : n.inputs)
      if (src.node == id) src.node = new_id;
  if (auto it = editor.positions.find(id); it != editor.positions.end()) {
    editor.positions[new_id] = it->second;
    editor.positions.erase(id);
  }
  reindex();
}

std::string Graph::check_link(const PortRef& from, const std::string& to_node, const std::string& to_port) const {
  const Node* src = find(from.node);
  if (!src) return "no node '" + from.node + "'";
  const Node* dst = find(to_node);
  if (!dst) return "no node '" + to_node + "'";
  const auto* out = src->type->find_output(from.port);
  if (!out) return "node '" + from.node + "' (" + src->type->name + ") has no output '" + from.port + "'";
  const auto* in = dst->type->find_input(to_port);
  if (!in) return "node '" + to_node + "' (" + dst->type->name + ") has no input '" + to_port + "'";
  if (out->type != in->type)
    return "type mismatch: " + from.str() + " is " + std::string(to_string(out->type)) + " but " + to_node + "." +
           to_port + " takes " + std::string(to_string(in->type));
  if (from.node == to_node) return "a node cannot feed itself (" + to_node + ")";
  const auto up = upstream(from.node);
  if (std::find(up.begin(), up.end(), to_node) != up.end())
    return "linking " + from.str() + " to " + to_node + "." + to_port + " would make a cycle";
  return {};
}

void Graph::connect(const PortRef& from, const std::string& to_node, const std::string& to_port) {
  if (auto why = check_link(from, to_node, to_port); !why.empty()) throw GraphError(why);
  find(to_node)->inputs[to_port] = from;
}

void Graph::disconnect(const std::string& to_node, const std::string& to_port) {
  Node* dst = find(to_node);
  if (!dst) throw GraphError("no node '" + to_node + "'");
  dst->inputs.erase(to_port);
}

void Graph::set_param(const std::string& node, const std::string& name, ParamValue value) {
  Node* n = find(node);
  if (!n) throw GraphError("no node '" + node + "'");
  const auto* decl = n->type->find_param(name);
  if (!decl) throw GraphError("node '" + node + "' (" + n->type->name + ") has no parameter '" + name + "'");
  if (auto why = decl->check(value); !why.empty()) throw GraphError(node + "." + name + ": " + why);
  n->params[name] = std::move(value);
}

void Graph::reset_param(const std::string& node, const std::string& name) {
  Node* n = find(node);
  if (!n) throw GraphError("no node '" + node + "'");
  n->params.erase(name);
}

const ParamValue& Graph::param(const std::string& node, const std::string& name) const {
  const Node& n = at(node);
  if (auto it = n.params.find(name); it != n.params.end()) return it->second;
  const auto* decl = n.type->find_param(name);
  if (!decl) throw GraphError("node '" + node + "' (" + n.type->name + ") has no parameter '" + name + "'");
  return decl->default_value;
}

std::vector<ParamValue> Graph::effective_params(const Node& node) const {
  std::vector<ParamValue> values;
  values.reserve(node.type->params.size());
  for (const auto& decl : node.type->params) {
    const auto it = node.params.find(decl.name);
    values.push_back(it != node.params.end() ? it->second : decl.default_value);
  }
  return values;
}

std::vector<std::string> Graph::topological_order() const {
  // Depth-first, visiting nodes in file order so the order is stable.
  std::vector<std::string> order;
  std::unordered_map<std::string, int> state;  // 0 new, 1 on stack, 2 done
  std::function<void(const Node&)> visit = [&](const Node& n) {
    int& s = state[n.id];
    if (s == 2) return;
    if (s == 1) throw GraphError("the graph has a cycle through '" + n.id + "'");
    s = 1;
    for (const auto& [port, src] : n.inputs)
      if (const Node* up = find(src.node)) visit(*up);
    state[n.id] = 2;
    order.push_back(n.id);
  };
  for (const auto& n : nodes_) visit(n);
  return order;
}

std::vector<std::string> Graph::upstream(const std::string& id) const {
  return upstream(id, [](const std::string&) { return false; });
}

std::vector<std::string> Graph::upstream(const std::string& id,
                                         const std::function<bool(const std::string&)>& stop_at) const {
  std::vector<std::string> out;
  std::set<std::string> seen;
  std::vector<std::string> stack{id};
  while (!stack.empty()) {
    const auto cur = stack.back();
    stack.pop_back();
    const Node* n = find(cur);
    if (!n) continue;
    for (const auto& [port, src] : n->inputs)
      if (seen.insert(src.node).second) {
        out.push_back(src.node);
        if (!stop_at(src.node)) stack.push_back(src.node);
      }
  }
  return out;
}

std::vector<std::string> Graph::downstream(const std::string& id) const {
  std::vector<std::string> out;
  std::set<std::string> seen{id};
  bool grew = true;
  while (grew) {
    grew = false;
    for (const auto& n : nodes_) {
      if (seen.count(n.id)) continue;
      for (const auto& [port, src] : n.inputs)
        if (seen.count(src.node)) {
          seen.insert(n.id);
          out.push_back(n.id);
          grew = true;
          break;
        }
    }
  }
  return out;
}

}  // namespace orogen
