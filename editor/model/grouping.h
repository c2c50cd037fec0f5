#pragma once
// Group and ungroup (Ctrl+G, Ctrl+Shift+G): a selection of nodes becomes a subgraph asset file plus one
// instance wired the way the selection was; an instance becomes its asset's nodes again. Both are one undo
// step of the document (the asset file stays on disk: redo needs it). See docs/subgraphs.md, "In the editor".
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "editor/model/document.h"
#include "graph/subgraph.h"

namespace orogen::editor {

// A free "NAME.orogen-subgraph.json" in `dir` (group, group2, ...), not taken by a file.
std::filesystem::path free_asset_path(const std::filesystem::path& dir, const std::string& base = "group");

// The folder relative asset references and input paths of a document resolve against: its file's folder,
// else the graph's directory (empty: the current directory).
std::filesystem::path document_directory(const Document& document);

struct GroupResult {
  std::string instance;              // the new instance's id
  std::filesystem::path asset_file;  // the asset written
  const SubgraphAsset* asset = nullptr;
};
// Groups `ids` of the document: writes the asset to `asset_file` (default: a free name beside the document's
// file, which must then have one), and replaces the selection with an instance wired like it, in one undo
// step. The asset and the rewrite are graph/subgraph_extract.h's, as `orogen subgraph extract` makes them,
// except that writers may be grouped. Throws DocumentError (nothing written, nothing changed) when the
// selection cannot be grouped.
GroupResult group_nodes(Document& document, const std::vector<std::string>& ids, std::filesystem::path asset_file = {});

// Replaces instance `id` of `graph` by its asset's nodes (one level): the exposed values written into the
// parameters they map to, links rewired through the interface, positions around the instance's. Inner ids
// keep their names when free. Returns the new nodes' ids. Throws GraphError if `id` is not an instance.
std::vector<std::string> inline_instance(Graph& graph, const std::string& id, const std::filesystem::path& graph_dir);
// The same as one undo step of the document.
std::vector<std::string> ungroup_node(Document& document, const std::string& id);

// "Make unique": instance `id` gets its own copy of its asset, embedded in the document (graph/subgraph_unique.h),
// in one undo step. Returns the embedded asset's name. Throws DocumentError with the reason.
// `holder`: the graph of the document whose file will hold the copy, when `document` is an embedded asset of it
// being edited (SubgraphNavigator::make_unique).
std::string make_unique_node(Document& document, const std::string& id, const Graph* holder = nullptr);

}  // namespace orogen::editor
