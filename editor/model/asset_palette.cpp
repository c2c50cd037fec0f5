#include "editor/model/asset_palette.h"

#include <map>
#include <memory>
#include <mutex>

#include "graph/registry.h"
#include "graph/subgraph.h"

namespace orogen::editor {

LibraryPalette library_palette_types() {
  // Entries are kept per asset: an asset whose file changed is a new asset, with a new entry.
  static std::mutex mutex;
  static std::map<const SubgraphAsset*, std::unique_ptr<NodeType>> entries;
  LibraryPalette out;
  for (const auto& file : list_subgraph_library()) {
    const AssetLoad load = load_subgraph_asset(file.name, {});
    if (!load.asset) {
      out.errors.push_back(load.error);
      continue;
    }
    std::lock_guard lock(mutex);
    auto& entry = entries[load.asset];
    if (!entry) {
      entry = std::make_unique<NodeType>(load.asset->type);
      entry->name = file.name;  // what the palette shows and searches, and the instance's reference
    }
    out.types.push_back(entry.get());
  }
  return out;
}

std::vector<const NodeType*> palette_types_with_library(std::vector<std::string>* errors) {
  std::vector<const NodeType*> types = NodeRegistry::instance().all();
  LibraryPalette library = library_palette_types();
  types.insert(types.end(), library.types.begin(), library.types.end());
  if (errors) *errors = std::move(library.errors);
  return types;
}

}  // namespace orogen::editor
