// Subgraph assets: finding and loading them (with recursion refused), the instance node type, interface
// signatures, and the expansion of instances into plain nodes. The "interface" section itself is read by the
// graph file reader (graph_file.cpp), which reports its problems like any others.
#include "graph/subgraph.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <deque>
#include <fstream>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "graph/asset_reference.h"
#include "graph/exec_context.h"
#include "graph/graph_file.h"

namespace orogen {

using nlohmann::json;
namespace fs = std::filesystem;

std::vector<fs::path> subgraph_library_dirs() {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("OROGEN_LIBRARY_PATH")) {
    std::stringstream list(env);
    std::string entry;
    while (std::getline(list, entry, ':'))
      if (!entry.empty()) dirs.emplace_back(entry);
  }
#ifdef OROGEN_SHIPPED_LIBRARY_DIR
  dirs.emplace_back(OROGEN_SHIPPED_LIBRARY_DIR);
#endif
  return dirs;
}

std::vector<LibraryAssetFile> list_subgraph_library() {
  std::map<std::string, fs::path> found;
  const std::string suffix = kSubgraphFileSuffix;
  for (const auto& dir : subgraph_library_dirs()) {
    std::error_code ec;
    std::vector<fs::path> files;
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) files.push_back(it->path());
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
      const std::string name = file.filename().string();
      if (name.size() <= suffix.size() || name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
        continue;
      found.emplace(name.substr(0, name.size() - suffix.size()), file);  // the first folder wins
    }
  }
  std::vector<LibraryAssetFile> out;
  for (auto& [name, file] : found) out.push_back({name, file});
  return out;
}

namespace {

// The type of an asset's instances: the interface's ports and exposed parameters. It never runs: the
// evaluator expands instances first.
NodeType instance_type(const SubgraphAsset& asset) {
  const SubgraphInterface& in = asset.interface();
  NodeType t;
  t.name = kSubgraphTypeName;
  t.category = "subgraph";
  t.description = in.description;
  t.version = in.asset_version;
  for (const auto& i : in.inputs) t.inputs.push_back(i.port);
  for (const auto& o : in.outputs) t.outputs.push_back(o.port);
  for (const auto& p : in.params) t.params.push_back(p.decl);
  t.subgraph = &asset;
  const std::string name = asset.name;
  t.execute = [name](ExecContext&) {
    throw std::runtime_error("subgraph instance of '" + name + "' was not expanded before evaluation");
  };
  return t;
}

// Assets by file, content and the nested assets they use: equal ones are shared, changed ones are new.
const SubgraphAsset* intern(std::unique_ptr<SubgraphAsset> asset, const std::string& text) {
  static std::mutex mutex;
  static std::map<std::string, std::unique_ptr<SubgraphAsset>> assets;
  // An embedded asset's relative paths resolve in the folder of the file holding it: part of what it is.
  std::string key = asset->file.string() + '\0' + asset->name + '\0' + asset->embedded + '\0' +
                    (asset->embedded.empty() ? std::string() : asset->graph.directory.string()) + '\0' + text;
  for (const auto& node : asset->graph.nodes())
    if (node.type->subgraph) key += '\0' + std::to_string(reinterpret_cast<std::uintptr_t>(node.type->subgraph));
  std::lock_guard lock(mutex);
  auto& slot = assets[key];
  if (!slot) {
    slot = std::move(asset);
    slot->type = instance_type(*slot);
  }
  return slot.get();
}

std::string join_names(const std::vector<std::string>& names) {
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  return list;
}

// Reads embedded asset `name` from `text` in scope `scope` of `context`: recursion refused with the cycle, the
// document checked like an asset file (format, version, interface, its own instances).
AssetLoad parse_embedded(const std::string& name, const std::string& text, AssetLoadContext& context,
                         std::size_t scope) {
  AssetLoad result;
  const std::string shown = kEmbeddedReferencePrefix + name;
  const fs::path key = context.scopes[scope].key + shown;
  if (const auto it = std::find(context.files.begin(), context.files.end(), key); it != context.files.end()) {
    std::string cycle;
    for (std::size_t k = static_cast<std::size_t>(it - context.files.begin()); k < context.chain.size(); ++k)
      cycle += context.chain[k] + " -> ";
    result.error = "subgraph asset '" + shown + "' contains itself: " + cycle + shown;
    return result;
  }
  if (const auto it = context.loaded.find(key); it != context.loaded.end()) {
    result.asset = it->second;
    return result;
  }
  const fs::path directory = context.scopes[scope].directory;
  context.chain.push_back(shown);
  context.files.push_back(key);
  context.embedded_document = true;
  LoadOptions options;
  options.directory = directory;
  options.asset_context = &context;
  LoadResult loaded = parse_graph(text, options);
  context.embedded_document = false;
  context.chain.pop_back();
  context.files.pop_back();
  if (!loaded.ok()) {
    result.error = "embedded subgraph asset '" + shown + "' is invalid:";
    for (const auto& d : loaded.diagnostics) result.error += "\n  /subgraphs/" + name + d.str();
    return result;
  }
  if (!loaded.graph->interface) {
    result.error = "embedded subgraph asset '" + shown + "' has no \"interface\" section: it is a graph, not an asset";
    return result;
  }
  auto asset = std::make_unique<SubgraphAsset>();
  asset->name = name;
  asset->embedded = name;
  asset->graph = std::move(*loaded.graph);
  asset->graph.directory = directory;
  result.asset = intern(std::move(asset), text);
  context.loaded[key] = result.asset;
  context.scopes[scope].loaded[name] = result.asset;
  return result;
}

AssetLoad load_embedded_reference(const std::string& reference, AssetLoadContext& context) {
  AssetLoad result;
  const std::string name = reference.substr(1);
  if (context.scopes.empty()) {
    result.error = "'" + reference + "' names an embedded subgraph asset, which only a graph file can hold";
    return result;
  }
  const std::size_t scope = context.scopes.size() - 1;
  context.scopes[scope].attempted.insert(name);
  if (const auto it = context.scopes[scope].loaded.find(name); it != context.scopes[scope].loaded.end()) {
    result.asset = it->second;
    return result;
  }
  const nlohmann::json* section = context.scopes[scope].section;
  if (!section || !section->contains(name)) {
    std::vector<std::string> names;
    if (section)
      for (const auto& [n, entry] : section->items())
        if (Graph::valid_id(n)) names.push_back(kEmbeddedReferencePrefix + n);
    for (const auto& [n, asset] : context.scopes[scope].loaded)
      if (!section || !section->contains(n)) names.push_back(kEmbeddedReferencePrefix + n);
    result.error = "embedded subgraph asset '" + reference + "' not found: " +
                   (names.empty() ? std::string("the file has no embedded assets (no \"subgraphs\" section)")
                                  : "the file's embedded assets are " + join_names(names));
    return result;
  }
  return parse_embedded(name, (*section)[name].dump(), context, scope);
}

}  // namespace

std::string SubgraphAsset::location() const {
  return embedded.empty() ? file.string()
                          : "embedded asset '" + std::string(1, kEmbeddedReferencePrefix) + embedded + "'";
}

AssetLoad load_embedded_asset(const std::string& name, const std::string& text, const fs::path& directory,
                              const std::map<std::string, const SubgraphAsset*>& siblings) {
  AssetLoadContext context;
  EmbeddedScope scope;
  scope.key = "given:" + directory.string();
  scope.directory = directory;
  scope.loaded = siblings;
  scope.loaded.erase(name);
  context.scopes.push_back(std::move(scope));
  return parse_embedded(name, text, context, 0);
}

std::map<std::string, const SubgraphAsset*> embedded_assets_of(const Graph& graph) {
  std::map<std::string, const SubgraphAsset*> out;
  std::vector<const Graph*> pending{&graph};
  while (!pending.empty()) {
    const Graph* g = pending.back();
    pending.pop_back();
    for (const auto& node : g->nodes()) {
      const SubgraphAsset* asset = node.type->subgraph;
      if (!asset || asset->embedded.empty()) continue;
      const auto [it, added] = out.emplace(asset->embedded, asset);
      if (added) {
        pending.push_back(&asset->graph);
      } else if (it->second != asset && serialize_graph(it->second->graph) != serialize_graph(asset->graph)) {
        throw GraphError("two different embedded subgraph assets are named '#" + asset->embedded + "' (instance '" +
                         node.id + "' uses one of them); make one of them unique again");
      }
    }
  }
  return out;
}

std::string free_embedded_name(const Graph& graph, const std::string& base, const Graph* holder) {
  std::string name = base;
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '_';
  if (name.empty() || (!std::isalpha(static_cast<unsigned char>(name[0])) && name[0] != '_')) name = "_" + name;
  if (name.size() > 100) name.resize(100);
  auto taken = embedded_assets_of(graph);
  if (holder) taken.merge(embedded_assets_of(*holder));
  std::string candidate = name;
  for (int k = 2; taken.count(candidate); ++k) candidate = name + std::to_string(k);
  return candidate;
}

AssetLoad load_subgraph_asset(const std::string& reference, const fs::path& directory, AssetLoadContext* context) {
  AssetLoadContext own;
  if (!context) context = &own;
  AssetLoad result;
  fs::path file;
  std::string name;
  if (reference.empty()) {
    result.error = "the asset reference is empty";
    return result;
  }
  if (is_embedded_reference(reference)) return load_embedded_reference(reference, *context);
  if (is_path_reference(reference)) {
    file = fs::path(reference).is_absolute() ? fs::path(reference) : directory / reference;
    name = asset_name_of(file);
    if (!fs::is_regular_file(file)) {
      result.error = "subgraph asset '" + reference + "' not found: no file " + file.lexically_normal().string();
      return result;
    }
  } else {
    name = reference;
    const auto dirs = subgraph_library_dirs();
    for (const auto& dir : dirs)
      if (fs::is_regular_file(dir / (reference + kSubgraphFileSuffix))) {
        file = dir / (reference + kSubgraphFileSuffix);
        break;
      }
    if (file.empty()) {
      std::string where;
      for (const auto& dir : dirs) where += (where.empty() ? "" : ", ") + dir.string();
      std::string hint;
      std::vector<std::string> names;
      for (const auto& entry : list_subgraph_library()) names.push_back(entry.name);
      result.error = "subgraph asset '" + reference + "' not found: no " + reference + kSubgraphFileSuffix +
                     " in the library folders (" + (where.empty() ? "none" : where) + ")";
      if (!names.empty()) {
        std::string list;
        for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
        result.error += "; the library has: " + list;
      }
      return result;
    }
  }
  std::error_code ec;
  fs::path canonical = fs::weakly_canonical(file, ec);
  if (ec) canonical = fs::absolute(file).lexically_normal();

  if (const auto it = std::find(context->files.begin(), context->files.end(), canonical); it != context->files.end()) {
    std::string cycle;
    for (std::size_t k = static_cast<std::size_t>(it - context->files.begin()); k < context->chain.size(); ++k)
      cycle += context->chain[k] + " -> ";
    result.error = "subgraph asset '" + name + "' contains itself: " + cycle + name;
    return result;
  }
  if (const auto it = context->loaded.find(canonical); it != context->loaded.end()) {
    result.asset = it->second;
    return result;
  }

  std::ifstream in(canonical, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  if (!in) {
    result.error = "cannot read subgraph asset '" + name + "' (" + canonical.string() + ")";
    return result;
  }
  const std::string text = buffer.str();
  context->chain.push_back(name);
  context->files.push_back(canonical);
  context->next_scope_key = canonical.string();  // "#name" inside it names its own embedded assets
  LoadOptions options;
  options.directory = canonical.parent_path();
  options.asset_context = context;
  LoadResult loaded = parse_graph(text, options);
  context->chain.pop_back();
  context->files.pop_back();
  if (!loaded.ok()) {
    result.error = "subgraph asset '" + name + "' (" + canonical.string() + ") is invalid:";
    for (const auto& d : loaded.diagnostics) result.error += "\n  " + d.str();
    return result;
  }
  if (!loaded.graph->interface) {
    result.error = "subgraph asset '" + name + "' (" + canonical.string() +
                   ") has no \"interface\" section: it is a graph, not an asset";
    return result;
  }
  auto asset = std::make_unique<SubgraphAsset>();
  asset->name = name;
  asset->file = canonical;
  asset->graph = std::move(*loaded.graph);
  asset->graph.directory = canonical.parent_path();
  result.asset = intern(std::move(asset), text);
  context->loaded[canonical] = result.asset;
  return result;
}

Node& add_subgraph_instance(Graph& graph, const SubgraphAsset& asset, const std::string& reference, std::string id) {
  if (id.empty()) id = graph.unique_id(asset.name);
  Node& node = graph.add_node(asset.type, std::move(id));
  node.asset = reference;
  return node;
}

json interface_signature(const SubgraphInterface& interface) {
  json sig = {{"inputs", json::object()}, {"outputs", json::object()}, {"params", json::object()}};
  for (const auto& i : interface.inputs) sig["inputs"][i.port.name] = std::string(to_string(i.port.type));
  for (const auto& o : interface.outputs) sig["outputs"][o.port.name] = std::string(to_string(o.port.type));
  for (const auto& p : interface.params) sig["params"][p.decl.name] = std::string(to_string(p.decl.type));
  return sig;
}

std::string describe_interface_change(const json& recorded, const json& current) {
  std::vector<std::string> changes;
  for (const auto& [section, what] : std::vector<std::pair<std::string, std::string>>{
           {"inputs", "input"}, {"outputs", "output"}, {"params", "param"}}) {
    const json empty = json::object();
    const json& before = recorded.contains(section) && recorded[section].is_object() ? recorded[section] : empty;
    const json& after = current.contains(section) && current[section].is_object() ? current[section] : empty;
    for (const auto& [name, type] : before.items()) {
      const std::string t = type.is_string() ? type.get<std::string>() : type.dump();
      if (!after.contains(name))
        changes.push_back(what + " '" + name + "' removed (was " + t + ")");
      else if (after[name] != type)
        changes.push_back(what + " '" + name + "' retyped " + t + " -> " + after[name].get<std::string>());
    }
    for (const auto& [name, type] : after.items())
      if (!before.contains(name)) changes.push_back(what + " '" + name + "' added (" + type.get<std::string>() + ")");
  }
  std::string text;
  for (const auto& c : changes) text += (text.empty() ? "" : "; ") + c;
  return text;
}

bool has_subgraphs(const Graph& graph) {
  return std::any_of(graph.nodes().begin(), graph.nodes().end(),
                     [](const Node& n) { return n.type->subgraph != nullptr; });
}

namespace {

class Expander {
 public:
  Expander(ExpandedGraph& out, const InstanceOverrides* overrides) : out_(out), overrides_(overrides) {}

  // Adds the nodes of `g` under `prefix`, then its links.
  void expand(const Graph& g, const std::string& prefix) {
    for (const auto& node : g.nodes()) {
      const std::string id = prefix + node.id;
      const SubgraphAsset* asset = node.type->subgraph;
      if (!asset) {
        Node& added = out_.graph.add_expanded_node(*node.type, id);
        added.params = node.params;
        // Input files named inside an asset are the asset's: they resolve against its folder.
        if (!prefix.empty()) absolutize_input_paths(added, g.directory);
        continue;
      }
      const std::size_t first = out_.graph.nodes().size();
      out_.types[id] = node.type;
      const auto extra = overrides_ ? overrides_->find(id) : InstanceOverrides::const_iterator();
      Graph inner = with_exposed_values(g, node, overrides_ && extra != overrides_->end() ? &extra->second : nullptr);
      expand(inner, id + "/");
      auto& outputs = out_.outputs[id];
      for (const auto& output : asset->interface().outputs) outputs.push_back(source(inner, id + "/", output.source));
      auto& nodes = out_.nodes[id];
      for (std::size_t k = first; k < out_.graph.nodes().size(); ++k) nodes.push_back(out_.graph.nodes()[k].id);
    }
    for (const auto& node : g.nodes())
      for (const auto& [port, from] : node.inputs) {
        const PortRef src = source(g, prefix, from);
        for (const auto& sink : sinks(prefix, node, port)) out_.graph.connect(src, sink.node, sink.name);
      }
  }

 private:
  static bool is_input_path(const ParamDecl& decl) { return decl.type == ParamType::Path && !decl.output_file; }

  // Relative input paths made absolute against `dir` (the current directory when empty, as the evaluator
  // resolves them for a graph without a folder).
  static ParamValue absolute_input_path(const ParamValue& value, const fs::path& dir) {
    const auto* text = std::get_if<std::string>(&value);
    if (!text || text->empty() || fs::path(*text).is_absolute()) return value;
    std::error_code ec;
    const fs::path base = dir.empty() ? fs::current_path(ec) : dir;
    return (base / *text).lexically_normal().string();
  }

  static void absolutize_input_paths(Node& node, const fs::path& dir) {
    for (const auto& decl : node.type->params) {
      if (!is_input_path(decl)) continue;
      const auto it = node.params.find(decl.name);
      const ParamValue& value = it != node.params.end() ? it->second : decl.default_value;
      if (const auto* text = std::get_if<std::string>(&value); text && !text->empty())
        node.params[decl.name] = absolute_input_path(value, dir);
    }
  }

  // The asset's graph with the instance's exposed values (`extra`, else set or default) written into their
  // targets. An input path set on the instance resolves against the folder of the graph the instance is in,
  // one from `extra` against the folder of the expanded graph.
  Graph with_exposed_values(const Graph& g, const Node& instance,
                            const std::map<std::string, ParamValue>* extra) const {
    const SubgraphAsset& asset = *instance.type->subgraph;
    Graph inner = asset.graph;
    for (const auto& p : asset.interface().params) {
      const auto over = extra ? extra->find(p.decl.name) : std::map<std::string, ParamValue>::const_iterator();
      const bool overridden = extra && over != extra->end();
      const bool set_here = instance.params.count(p.decl.name) > 0;
      ParamValue value = overridden ? over->second : g.param(instance.id, p.decl.name);
      if (is_input_path(p.decl) && (overridden || set_here))
        value = absolute_input_path(value, overridden ? out_.graph.directory : g.directory);
      for (const auto& t : p.targets) {
        try {
          inner.set_param(t.node, t.name, value);
        } catch (const GraphError& e) {
          throw GraphError("subgraph instance '" + instance.id + "' (asset '" + asset.name + "'): parameter '" +
                           p.decl.name + "' cannot set " + t.str() + ": " + e.what());
        }
      }
    }
    return inner;
  }

  // The expanded output that output `from` of a node of `g` stands for.
  PortRef source(const Graph& g, const std::string& prefix, const PortRef& from) const {
    const Node& node = g.at(from.node);
    if (!node.type->subgraph) return {prefix + from.node, from.port};
    const int index = node.type->output_index(from.port);
    return out_.outputs.at(prefix + from.node).at(static_cast<std::size_t>(index));
  }

  // The expanded input ports that input `port` of `node` (a node of the graph expanded under `prefix`) stands for.
  std::vector<SubgraphTarget> sinks(const std::string& prefix, const Node& node, const std::string& port) const {
    const SubgraphAsset* asset = node.type->subgraph;
    if (!asset) return {{prefix + node.id, port}};
    std::vector<SubgraphTarget> out;
    for (const auto& input : asset->interface().inputs) {
      if (input.port.name != port) continue;
      for (const auto& t : input.targets) {
        auto more = sinks(prefix + node.id + "/", asset->graph.at(t.node), t.name);
        out.insert(out.end(), more.begin(), more.end());
      }
    }
    return out;
  }

  ExpandedGraph& out_;
  const InstanceOverrides* overrides_;
};

}  // namespace

ExpandedGraph expand_subgraphs(const Graph& graph, const InstanceOverrides* overrides) {
  ExpandedGraph out;
  out.graph.domain = graph.domain;
  out.graph.directory = graph.directory;
  Expander(out, overrides).expand(graph, "");
  return out;
}

}  // namespace orogen
