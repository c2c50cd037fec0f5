#pragma once
// Choosing which parameters a subgraph asset exposes, from the inspector of its inner nodes (while the asset
// is entered or open): exposing adds an entry to the asset's "interface" "params" that maps to the inner
// parameter (its declaration, default and range are the inner one's, graph/subgraph.h), hiding removes it.
// Either changes the interface, so the asset version goes up: instances saved before say what changed.
#include <string>

#include "editor/model/document.h"

namespace orogen::editor {

// The exposed parameter that sets `node.param` of the asset `graph` is ("" when none or not an asset).
std::string exposed_as(const Graph& graph, const std::string& node, const std::string& param);

// Exposes (or hides) `node.param` of the asset the document holds, as one undo step. Throws DocumentError
// when the document is not an asset. Returns the exposed parameter's name (exposing) or "".
std::string set_exposed(Document& document, const std::string& node, const std::string& param, bool exposed);

}  // namespace orogen::editor
