#pragma once
// The graph: node instances with their parameter values and input links, the default domain, and the
// editor's layout. Edits are validated: links are type-checked and cycles are refused.
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/domain.h"
#include "graph/node_type.h"
#include "graph/param_value.h"

namespace orogen {

struct GraphError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// One end of a link: output `port` of node `node`. Written "node.port" in files.
struct PortRef {
  std::string node;
  std::string port;
  bool operator==(const PortRef&) const = default;
  std::string str() const { return node + "." + port; }
};

struct SubgraphInterface;

struct Node {
  std::string id;
  const NodeType* type = nullptr;
  // Subgraph instances (type->subgraph set, graph/subgraph.h): the asset as the file names it, a library name
  // or a path relative to the graph file. Empty for other nodes.
  std::string asset;
  std::map<std::string, ParamValue> params;  // explicitly set parameters; the rest take their defaults
  std::map<std::string, PortRef> inputs;     // input port name -> the output feeding it
};

// The world rectangle and resolution a graph is built at (the "domain" of the file).
struct GraphDomain {
  glm::dvec2 origin{0.0, 0.0};
  glm::dvec2 size{1024.0, 1024.0};
  glm::ivec2 resolution{256, 256};
  Domain to_domain() const { return Domain::from_extent(origin, size, resolution); }
  bool operator==(const GraphDomain&) const = default;
};

// Layout and view state the editor keeps in the file; ignored by evaluation.
struct EditorState {
  std::map<std::string, glm::dvec2> positions;  // node id -> canvas position
  bool operator==(const EditorState&) const = default;
};

class Graph {
 public:
  GraphDomain domain;
  EditorState editor;
  // The directory of the graph file it was loaded from (set by load_graph_file), against which relative
  // input paths (ReadHeightfield's `path`, ...) resolve; empty: the current directory. Not saved in the
  // file and not part of equality.
  std::filesystem::path directory;
  // Set for a subgraph asset (graph/subgraph.h): its typed inputs, outputs and exposed parameters.
  std::shared_ptr<const SubgraphInterface> interface;

  const std::vector<Node>& nodes() const { return nodes_; }
  const Node* find(const std::string& id) const;
  Node* find(const std::string& id);
  const Node& at(const std::string& id) const;  // throws GraphError if absent

  // Adds a node of a registered type. With an empty id, a unique one is made from the type name.
  // Throws GraphError for an unknown type, an invalid id or a duplicate id.
  Node& add_node(const std::string& type_name, std::string id = {});
  // Adds a node of a type not (necessarily) in the registry; used by tests and the loader.
  Node& add_node(const NodeType& type, std::string id = {});
  // Adds a node of an expanded subgraph instance, whose id is a path of valid ids ("instance/inner"); used by
  // expand_subgraphs (graph/subgraph.h) only, so such ids never appear in files.
  Node& add_expanded_node(const NodeType& type, std::string id);
  // Removes the node, every link from or to it and its editor position.
  void remove_node(const std::string& id);
  // Renames a node, updating links and editor position.
  void rename_node(const std::string& id, const std::string& new_id);

  // Links output `from` to input `to_port` of `to_node`, replacing the link already on that input.
  // Throws GraphError for a missing node or port, a type mismatch, or a link that would make a cycle.
  void connect(const PortRef& from, const std::string& to_node, const std::string& to_port);
  // Why connect(from, to_node, to_port) would fail, or an empty string if it would succeed.
  std::string check_link(const PortRef& from, const std::string& to_node, const std::string& to_port) const;
  void disconnect(const std::string& to_node, const std::string& to_port);

  // Sets a parameter after checking its type and range; throws GraphError with the reason.
  void set_param(const std::string& node, const std::string& name, ParamValue value);
  // Returns the parameter to its default.
  void reset_param(const std::string& node, const std::string& name);
  // The effective value: explicitly set, or the default.
  const ParamValue& param(const std::string& node, const std::string& name) const;
  // Every parameter's effective value, in declaration order.
  std::vector<ParamValue> effective_params(const Node& node) const;

  // Node ids with every node after the nodes feeding it; throws GraphError on a cycle.
  std::vector<std::string> topological_order() const;
  // Ids of the nodes that (transitively) feed `id`, not including it.
  std::vector<std::string> upstream(const std::string& id) const;
  // The same, without walking past a node for which `stop_at` is true: it is listed, the nodes that reach `id` only
  // through such nodes are not.
  std::vector<std::string> upstream(const std::string& id,
                                    const std::function<bool(const std::string&)>& stop_at) const;
  // Ids of the nodes that `id` (transitively) feeds, not including it.
  std::vector<std::string> downstream(const std::string& id) const;
  // A fresh id: `base` if free, else base2, base3, ...
  std::string unique_id(const std::string& base) const;

  static bool valid_id(const std::string& id);

  bool operator==(const Graph& other) const;

 private:
  void reindex();
  std::vector<Node> nodes_;
  std::unordered_map<std::string, std::size_t> index_;
};

bool operator==(const Node& a, const Node& b);

}  // namespace orogen
