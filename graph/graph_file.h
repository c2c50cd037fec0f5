#pragma once
// The graph file: JSON, readable and diff-friendly (see DESIGN.md, "The graph file").
//
// Loading reports every problem at once, each with its JSON path and node id, instead of stopping at the
// first. Files of older format versions are migrated; newer ones are refused.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "graph/graph.h"

namespace orogen {

inline constexpr int kGraphFormatVersion = 7;
inline constexpr const char* kGraphFormatName = "orogen-graph";

struct Diagnostic {
  std::string path;         // JSON pointer of the offending value, e.g. "/nodes/2/params/octaves"
  std::string node;         // id of the node concerned, or "" for file-level problems
  std::string message;      // what is wrong, and what would be right
  std::string str() const;  // "path [node id]: message"
};

// A link of the file left out of a partially loaded graph (LoadOptions::keep_partial).
struct DroppedLink {
  PortRef from;         // as written ("node.port"); the node or port may not exist
  std::string to_node;  // the node whose input it fed
  std::string to_port;
  std::string reason;
};

struct LoadResult {
  std::optional<Graph> graph;  // set only when there are no diagnostics (unless keep_partial)
  std::vector<Diagnostic> diagnostics;
  std::vector<DroppedLink> dropped_links;  // keep_partial: the links left out, and why
  // Problems that do not stop a build: a node no output needs with a required input unconnected (see
  // graph/idle_nodes.h), which the evaluator leaves out.
  std::vector<Diagnostic> warnings;
  bool ok() const { return graph.has_value() && diagnostics.empty(); }
  std::string error_text() const;  // every diagnostic, one per line
};

struct AssetLoadContext;  // graph/subgraph.h

struct LoadOptions {
  // Accept links to nodes that are not in the file and drop them (pasting a fragment in the editor).
  bool drop_dangling_links = false;
  // Accept nodes whose required inputs are not connected (a work in progress saved by the editor); the
  // evaluator reports them when such a node is evaluated.
  bool allow_unconnected_inputs = false;
  // Return what can be read even when there are diagnostics, so the editor can show a broken file with its
  // problems marked instead of nothing: parameters with invalid values keep their defaults, a node of an
  // unknown type becomes a placeholder of that type name with the ports its links use (its evaluation fails
  // with the reason; its parameters are not kept), broken links and the link closing each cycle are left
  // out (see LoadResult::dropped_links), duplicate and invalid ids are dropped. A file that is not a graph
  // (not JSON, another format, a newer version) still gives no graph.
  bool keep_partial = false;
  // Where subgraph assets named by a relative path resolve (graph/subgraph.h); load_graph_file sets it to the
  // file's folder when empty. Empty: the current directory.
  std::filesystem::path directory;
  // The assets being loaded around this file (recursion detection); set by load_subgraph_asset.
  AssetLoadContext* asset_context = nullptr;
};

LoadResult parse_graph(std::string_view json_text, const LoadOptions& options = {});
inline constexpr std::size_t kMaxGraphFileBytes = std::size_t(64) << 20;  // larger files are refused
LoadResult load_graph_file(const std::filesystem::path& path, const LoadOptions& options = {});

// Pretty-printed, stable JSON: node order as in the graph, only explicitly set parameters.
std::string serialize_graph(const Graph& graph);
// Atomic: writes a temporary file beside `path`, then renames it over. Throws std::runtime_error.
void save_graph_file(const Graph& graph, const std::filesystem::path& path);

// A migration turns a file of format version `from_version` into version from_version + 1, in place.
using GraphMigration = std::function<void(nlohmann::json& file)>;
void register_graph_migration(int from_version, GraphMigration migration);
// Runs the migrations of a parsed graph file up to kGraphFormatVersion in place, keeping everything else of
// the file (what `orogen migrate` writes back); returns the version it had. Throws std::runtime_error for a
// file without an integer version, a newer version or a version no migration starts from.
int migrate_graph_document(nlohmann::json& doc);

// Parameter values <-> JSON, as used in the "params" object of a node.
nlohmann::json param_to_json(const ParamValue& value);
// Converts and checks (type, range, choices); returns nullopt and sets `error` on failure.
std::optional<ParamValue> param_from_json(const nlohmann::json& j, const ParamDecl& decl, std::string& error);
// Parses command-line text for `--set node.param=TEXT`: JSON if it parses, else a bare string.
std::optional<ParamValue> param_from_text(const std::string& text, const ParamDecl& decl, std::string& error);

}  // namespace orogen
