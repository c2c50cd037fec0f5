#include "graph/asset_reference.h"

#include "graph/subgraph.h"

namespace orogen {

bool is_path_reference(const std::string& reference) {
  if (is_embedded_reference(reference)) return false;
  return reference.find('/') != std::string::npos || reference.find('\\') != std::string::npos ||
         (reference.size() >= 5 && reference.compare(reference.size() - 5, 5, ".json") == 0);
}

bool is_embedded_reference(const std::string& reference) { return !reference.empty() && reference[0] == '#'; }

std::string asset_name_of(const std::filesystem::path& file) {
  std::string name = file.filename().string();
  const std::string suffix = kSubgraphFileSuffix;
  if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0)
    return name.substr(0, name.size() - suffix.size());
  return file.stem().string();
}

}  // namespace orogen
