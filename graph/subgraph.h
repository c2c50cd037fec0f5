#pragma once
// Reusable subgraphs (docs/subgraphs.md): a subgraph asset is a graph file with an "interface" section (typed
// inputs and outputs, exposed parameters, an asset version); a graph uses it through a node of type
// "Subgraph" that names the asset. Instances are linked: they hold no copy of the asset's nodes, and the
// evaluator expands them into plain nodes ("instance/inner") before planning.
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "graph/graph.h"

namespace orogen {

inline constexpr const char* kSubgraphTypeName = "Subgraph";
inline constexpr const char* kSubgraphFileSuffix = ".orogen-subgraph.json";

// An inner node's input port or parameter: "node.name" in files.
struct SubgraphTarget {
  std::string node, name;
  std::string str() const { return node + "." + name; }
};

struct SubgraphInput {
  PortDecl port;
  std::vector<SubgraphTarget> targets;  // inner input ports fed by it (at least one)
};
struct SubgraphOutput {
  PortDecl port;
  PortRef source;  // the inner output it presents
};
struct SubgraphParam {
  ParamDecl decl;
  // Inner parameters it sets: a node's parameter, or an exposed parameter of a nested instance (promotion).
  std::vector<SubgraphTarget> targets;
};

struct SubgraphInterface {
  int asset_version = 1;
  std::string description;
  std::vector<SubgraphInput> inputs;
  std::vector<SubgraphOutput> outputs;
  std::vector<SubgraphParam> params;
  std::string json_text;  // the section as read, written back unchanged by serialize_graph
};

// A loaded asset. Assets live for the whole program (instance node types point into them); loading the same
// file content again returns the same asset.
struct SubgraphAsset {
  std::string name;            // the library name, or the file name without ".orogen-subgraph.json"
  std::filesystem::path file;  // absolute; empty for an embedded asset
  // An embedded asset: its name in the "subgraphs" section of the graph file holding it (instances name it
  // "#name"); empty for an asset file. Its relative paths resolve against that file's folder (graph.directory).
  std::string embedded;
  Graph graph;    // the inner graph; graph.interface is set
  NodeType type;  // the type of its instances: the interface's ports and exposed parameters
  const SubgraphInterface& interface() const { return *graph.interface; }
  // Where it comes from, for messages: its file, or "embedded asset '#name'".
  std::string location() const;
};

inline constexpr char kEmbeddedReferencePrefix = '#';

// Where library names resolve: the folders of OROGEN_LIBRARY_PATH (':'-separated, searched first, so a user
// asset can stand in for a shipped one), then the shipped graphs/library.
std::vector<std::filesystem::path> subgraph_library_dirs();
struct LibraryAssetFile {
  std::string name;
  std::filesystem::path file;
};
// Every asset file in the library folders, by name (the first folder that has a name wins).
std::vector<LibraryAssetFile> list_subgraph_library();

// The embedded assets an instance's "#name" can name: the "subgraphs" section of the file being read (an
// embedded asset shares the section of the file it is in), or assets already loaded for it.
struct EmbeddedScope {
  std::string key;                          // the file holding the section (or "graph"): keys recursion checks
  std::filesystem::path directory;          // that file's folder: relative paths in embedded assets resolve there
  const nlohmann::json* section = nullptr;  // the "subgraphs" object as read, if any
  std::map<std::string, const SubgraphAsset*> loaded;  // by name: read from the section, or given
  std::set<std::string> attempted;                     // names looked up (loaded or not)
};

// The chain of assets being loaded, to refuse recursion with the cycle named, and the assets loaded so far.
struct AssetLoadContext {
  std::vector<std::string> chain;            // asset names, outermost first ("#name" for embedded ones)
  std::vector<std::filesystem::path> files;  // their files ("FILE#name" for embedded ones)
  std::map<std::filesystem::path, const SubgraphAsset*> loaded;
  // One per file being read, innermost last; the graph reader pushes and pops them.
  std::vector<EmbeddedScope> scopes;
  // Set by load_subgraph_asset for the reader of an embedded asset's document: it uses the current scope and
  // may not have a "subgraphs" section of its own. Set for the reader of an asset file: the key of its scope.
  bool embedded_document = false;
  std::string next_scope_key;
};

struct AssetLoad {
  const SubgraphAsset* asset = nullptr;
  std::string error;  // set when asset is null: missing, recursive, or invalid (with the file's diagnostics)
};
// Loads the asset `reference` names: "#name" (an embedded asset of the file being read: context->scopes), a
// path (it contains '/' or ends with ".json") relative to `directory`, or a library name.
AssetLoad load_subgraph_asset(const std::string& reference, const std::filesystem::path& directory,
                              AssetLoadContext* context = nullptr);

// An embedded asset from its document `text` (an asset document: format, version, interface, nodes), named
// `name` ("#name" in instances), its relative paths resolving against `directory`. "#other" instances inside
// it resolve among `siblings` (the other embedded assets of the same graph). Equal content gives the same asset.
AssetLoad load_embedded_asset(const std::string& name, const std::string& text, const std::filesystem::path& directory,
                              const std::map<std::string, const SubgraphAsset*>& siblings = {});

// The embedded assets a graph's instances use, by name, at any depth through embedded assets (not through asset
// files: "#name" inside an asset file names that file's own embedded assets). Throws GraphError when two
// different assets have the same name.
std::map<std::string, const SubgraphAsset*> embedded_assets_of(const Graph& graph);

// A name for a new embedded asset: `base` (made an identifier) if no embedded asset of `graph` (nor of `holder`,
// when given) has it, else base2, base3, ...
std::string free_embedded_name(const Graph& graph, const std::string& base, const Graph* holder = nullptr);

// A new instance of `asset` in `graph`, naming it by `reference` in files.
Node& add_subgraph_instance(Graph& graph, const SubgraphAsset& asset, const std::string& reference,
                            std::string id = {});

// {"inputs": {"name": "Type"}, "outputs": {...}, "params": {...}}: what an instance records of the interface
// it was made with, so a changed asset can say what changed.
nlohmann::json interface_signature(const SubgraphInterface& interface);
// "input 'mask' added (Heightfield); param 'gain' removed; output 'color' retyped Image -> Heightfield", or ""
// when the signatures are equal.
std::string describe_interface_change(const nlohmann::json& recorded, const nlohmann::json& current);

bool has_subgraphs(const Graph& graph);

// A graph with every instance replaced, recursively, by its asset's nodes. Inner nodes are named
// "instance/inner" (deeper: "a/b/inner"); an instance's exposed parameter values are written into the inner
// parameters they map to, and its links reach the inner ports its inputs map to.
struct ExpandedGraph {
  Graph graph;
  // Every instance, at any depth (expanded id, e.g. "a" or "a/b"): the expanded output feeding each of its
  // interface outputs (in interface order), and the expanded ids of all the plain nodes inside it.
  std::map<std::string, std::vector<PortRef>> outputs;
  std::map<std::string, std::vector<std::string>> nodes;
  std::map<std::string, const NodeType*> types;  // every instance's type (its exposed parameters)
};
// Exposed-parameter values for instances by expanded id ("a/b"), applied instead of the values the graph or
// asset gives them: `--set a/b.param=value` on a nested instance. Values must suit the instance's declarations.
using InstanceOverrides = std::map<std::string, std::map<std::string, ParamValue>>;
// Throws GraphError naming the instance when an exposed value cannot be applied.
ExpandedGraph expand_subgraphs(const Graph& graph, const InstanceOverrides* overrides = nullptr);

}  // namespace orogen
