#pragma once
// An asset's interface edited as JSON (a rename, an exposed parameter) becomes a whole interface again
// (targets and declarations resolved) by reading the asset back through the graph file reader.
#include <nlohmann/json.hpp>

#include "graph/graph.h"
#include "graph/graph_file.h"

namespace orogen::editor {

// `asset` with its interface section replaced by `interface_json`, serialized and parsed again (unconnected
// inputs accepted, as in any asset); keep_partial keeps what can be read when the section has problems.
LoadResult reread_with_interface(const Graph& asset, const nlohmann::json& interface_json, bool keep_partial);

}  // namespace orogen::editor
