#pragma once
// How a Subgraph instance names its asset: a path (relative to the graph file) or a library name.
#include <filesystem>
#include <string>

namespace orogen {

// Whether an instance's `asset` is a path (it contains a slash or ends in .json) rather than a library name.
bool is_path_reference(const std::string& reference);

// Whether an instance's `asset` names an embedded asset of the graph file ("#name", docs/subgraphs.md).
bool is_embedded_reference(const std::string& reference);

// The asset name a file stands for: its file name without ".orogen-subgraph.json" (else without its extension).
std::string asset_name_of(const std::filesystem::path& file);

}  // namespace orogen
