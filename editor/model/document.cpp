#include "editor/model/document.h"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "editor/model/interface_reread.h"
#include "editor/model/node_layout.h"
#include "graph/graph_file.h"
#include "graph/subgraph_unique.h"

namespace orogen::editor {

bool same_content(const Graph& a, const Graph& b) { return a.domain == b.domain && a.nodes() == b.nodes(); }

Document::Document() = default;

Document::Document(Graph graph, std::filesystem::path path) : graph_(std::move(graph)), path_(std::move(path)) {}

Document Document::open(const std::filesystem::path& path, bool room_for_thumbnails) {
  LoadOptions options;
  options.allow_unconnected_inputs = true;  // work in progress is a normal state in the editor
  options.keep_partial = true;              // a broken file opens with its problems marked
  auto result = load_graph_file(path, options);
  if (!result.graph) throw DocumentError("cannot open " + path.string() + ":\n" + result.error_text());
  // Files written by hand or by other tools may carry no layout: place those nodes, outside the history.
  place_unpositioned_nodes(*result.graph);
  if (room_for_thumbnails) make_room_for_thumbnails(*result.graph);
  Document doc(std::move(*result.graph), path);
  if (!result.diagnostics.empty()) {
    doc.load_problems_ = {std::move(result.diagnostics), std::move(result.dropped_links)};
    doc.mark_unsaved();  // what is shown is not what the file holds: saving writes the repaired graph
  }
  return doc;
}

std::vector<std::string> Document::LoadProblems::for_node(const std::string& id) const {
  std::vector<std::string> out;
  for (const auto& d : diagnostics)
    if (d.node == id) out.push_back(d.message);
  for (const auto& l : dropped_links)
    if (l.to_node == id && std::none_of(out.begin(), out.end(), [&](const std::string& m) { return m == l.reason; }))
      out.push_back("input '" + l.to_port + "' left unconnected: " + l.reason);
  return out;
}

std::string Document::display_name() const { return has_path() ? path_.filename().string() : "Untitled"; }

std::string Document::window_title() const { return display_name() + (dirty() ? "*" : "") + " - Orogen"; }

void Document::replace(Graph graph, std::uint64_t state) {
  const bool content_changed = !same_content(graph, graph_);
  graph_ = std::move(graph);
  state_ = state;
  ++revision_;
  if (content_changed) ++content_revision_;
}

bool Document::edit(const std::string& label, const std::function<void(Graph&)>& fn, const std::string& merge_key) {
  Graph next = graph_;
  fn(next);
  // The interface of an asset (exposing a parameter) is part of the document, though not of graph equality.
  const bool same_interface =
      next.interface == graph_.interface ||
      (next.interface && graph_.interface && next.interface->json_text == graph_.interface->json_text);
  if (next == graph_ && same_interface) return false;
  const auto state = history_.record(graph_, state_, label, merge_key);
  replace(std::move(next), state);
  return true;
}

bool Document::undo() {
  auto restored = history_.undo(graph_, state_);
  if (!restored) return false;
  replace(std::move(restored->graph), restored->state);
  return true;
}

bool Document::redo() {
  auto restored = history_.redo(graph_, state_);
  if (!restored) return false;
  replace(std::move(restored->graph), restored->state);
  return true;
}

std::string Document::add_node(const std::string& type_name, glm::dvec2 position) {
  std::string id;
  edit("Add " + type_name, [&](Graph& g) {
    id = g.add_node(type_name).id;
    g.editor.positions[id] = position;
  });
  return id;
}

void Document::remove_nodes(const std::vector<std::string>& ids) {
  if (ids.empty()) return;
  edit(ids.size() == 1 ? "Delete " + ids.front() : "Delete " + std::to_string(ids.size()) + " nodes", [&](Graph& g) {
    for (const auto& id : ids)
      if (g.find(id)) g.remove_node(id);
  });
}

void Document::connect(const PortRef& from, const std::string& to_node, const std::string& to_port) {
  edit("Connect " + from.str() + " to " + to_node + "." + to_port,
       [&](Graph& g) { g.connect(from, to_node, to_port); });
}

void Document::disconnect(const std::string& to_node, const std::string& to_port) {
  edit("Disconnect " + to_node + "." + to_port, [&](Graph& g) { g.disconnect(to_node, to_port); });
}

void Document::set_param(const std::string& node, const std::string& name, const ParamValue& value, bool gesture) {
  edit(
      "Set " + node + "." + name, [&](Graph& g) { g.set_param(node, name, value); },
      gesture ? "param:" + node + "." + name : std::string());
}

void Document::reset_param(const std::string& node, const std::string& name) {
  edit("Reset " + node + "." + name, [&](Graph& g) { g.reset_param(node, name); });
}

void Document::move_nodes(const std::vector<std::string>& ids, glm::dvec2 delta, bool gesture) {
  if (ids.empty()) return;
  edit(
      ids.size() == 1 ? "Move " + ids.front() : "Move " + std::to_string(ids.size()) + " nodes",
      [&](Graph& g) {
        for (const auto& id : ids)
          if (g.find(id)) g.editor.positions[id] += delta;
      },
      gesture ? std::string("move") : std::string());
}

namespace {

// The interface of an asset after inner node `id` became `new_id`: its "node.name" references follow.
std::shared_ptr<const SubgraphInterface> renamed_interface(const Graph& renamed, const std::string& id,
                                                           const std::string& new_id) {
  nlohmann::json in = nlohmann::json::parse(renamed.interface->json_text);
  auto rename = [&](nlohmann::json& ref) {
    if (!ref.is_string()) return;
    const std::string text = ref.get<std::string>();
    if (text.size() > id.size() && text.compare(0, id.size() + 1, id + ".") == 0) ref = new_id + text.substr(id.size());
  };
  for (const char* section : {"inputs", "outputs", "params"}) {
    if (!in.contains(section) || !in[section].is_array()) continue;
    for (auto& entry : in[section])
      for (const char* field : {"to", "from"}) {
        if (!entry.is_object() || !entry.contains(field)) continue;
        if (entry[field].is_array())
          for (auto& ref : entry[field]) rename(ref);
        else
          rename(entry[field]);
      }
  }
  const LoadResult reread = reread_with_interface(renamed, in, /*keep_partial=*/true);
  if (reread.graph && reread.graph->interface) return reread.graph->interface;
  auto text_only = std::make_shared<SubgraphInterface>(*renamed.interface);  // what could not be read whole
  text_only->json_text = in.dump();
  return text_only;
}

}  // namespace

void Document::rename_node(const std::string& id, const std::string& new_id) {
  edit("Rename " + id + " to " + new_id, [&](Graph& g) {
    g.rename_node(id, new_id);
    // In an asset, the interface names inner nodes: it follows the rename.
    if (g.interface) g.interface = renamed_interface(g, id, new_id);
  });
}

void Document::set_domain(const GraphDomain& domain) {
  edit("Change domain", [&](Graph& g) { g.domain = domain; });
}

bool Document::rebind_asset(const std::filesystem::path& file, const SubgraphAsset& asset) {
  auto rebind = [&](Graph& g) {
    bool any = false;
    for (const auto& n : g.nodes())
      if (n.type->subgraph && n.type->subgraph != &asset && n.type->subgraph->file == file) {
        g.find(n.id)->type = &asset.type;
        any = true;
      }
    return any;
  };
  history_.for_each_graph([&](Graph& g) { rebind(g); });
  const SubgraphAsset* before = nullptr;
  for (const auto& n : graph_.nodes())
    if (n.type->subgraph && n.type->subgraph->file == file) before = n.type->subgraph;
  if (!rebind(graph_)) return false;
  // Instances record the asset version and interface in the file: a changed one must be saved.
  if (before->interface().asset_version != asset.interface().asset_version ||
      interface_signature(before->interface()) != interface_signature(asset.interface()))
    mark_unsaved();
  ++revision_;
  ++content_revision_;
  return true;
}

bool Document::rebind_embedded(const SubgraphAsset& asset) {
  history_.for_each_graph([&](Graph& g) { replace_embedded_asset(g, asset); });
  if (!replace_embedded_asset(graph_, asset)) return false;
  mark_unsaved();  // the embedded asset is part of the file
  ++revision_;
  ++content_revision_;
  return true;
}

void Document::save() {
  if (!has_path()) throw std::runtime_error("the document has no file name yet: use Save As");
  save_graph_file(graph_, path_);
  saved_state_ = state_;
}

void Document::save_as(const std::filesystem::path& path) {
  save_graph_file(graph_, path);
  path_ = path;
  // Relative input paths now resolve beside the new file, as they will when it is opened again.
  std::error_code ec;
  const auto absolute = std::filesystem::absolute(path, ec);
  graph_.directory = (ec ? path : absolute).lexically_normal().parent_path();
  saved_state_ = state_;
}

}  // namespace orogen::editor
