#pragma once
// Library assets in the node palette, beside the node types: one entry per asset of the library folders
// (graph/subgraph.h), named after the asset, in the category "subgraph", with its interface's ports and
// description, so the palette's search and its link filter treat it like any node type. Choosing one adds
// an instance of the asset (CanvasController::confirm_palette).
#include <string>
#include <vector>

#include "graph/node_type.h"

namespace orogen::editor {

struct LibraryPalette {
  std::vector<const NodeType*> types;  // by asset name; they live for the whole program
  std::vector<std::string> errors;     // assets of the library that failed to load
};
LibraryPalette library_palette_types();

// The registered node types followed by the library assets (errors, if any, in `errors`).
std::vector<const NodeType*> palette_types_with_library(std::vector<std::string>* errors = nullptr);

// A palette entry standing for a library asset: its library name is the entry's name.
inline bool is_asset_entry(const NodeType& type) { return type.subgraph != nullptr; }

}  // namespace orogen::editor
