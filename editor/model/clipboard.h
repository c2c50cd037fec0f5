#pragma once
// Copy and paste of graph fragments as graph-file JSON: what lands on the system clipboard is an ordinary
// (partial) graph file, so fragments move between documents, editor instances and text editors.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include "graph/graph.h"

namespace orogen::editor {

// The nodes `ids` of `graph` with their parameters, the links between them and their layout, as a graph
// file. Links from nodes outside the fragment are left out.
std::string copy_fragment(const Graph& graph, const std::vector<std::string>& ids);

// Adds the nodes of a fragment to `graph` and returns their ids there. Ids already taken are renamed
// (fbm -> fbm2) and the fragment's links follow. With `at`, the fragment is moved so that its top-left
// node lands there; otherwise it keeps its positions. Links to nodes missing from the fragment are
// dropped. Throws DocumentError with the loader's diagnostics when the text is not a graph fragment.
std::vector<std::string> paste_fragment(Graph& graph, std::string_view text, std::optional<glm::dvec2> at = {});

}  // namespace orogen::editor
