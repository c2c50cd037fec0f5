#include "editor/model/node_library_preferences.h"

#include <algorithm>
#include <cstdlib>
#include <fstream>

#include <nlohmann/json.hpp>

#include "editor/model/normalized_path.h"
#include "graph/atomic_file.h"
#include "graph/node_library.h"

namespace orogen::editor {

NodeLibraryPreferences::NodeLibraryPreferences(std::filesystem::path file) : file_(std::move(file)) {
  std::ifstream in(file_);
  if (!in) return;
  try {
    const auto j = nlohmann::json::parse(in);
    for (const auto& entry : j.at("node_libraries"))
      if (entry.is_string()) files_.emplace_back(entry.get<std::string>());
  } catch (const std::exception&) {
    files_.clear();  // a damaged list is an empty one; the user adds the libraries again
  }
}

void NodeLibraryPreferences::add(const std::filesystem::path& path) {
  const auto p = normalized_path(path);
  if (std::find(files_.begin(), files_.end(), p) != files_.end()) return;
  files_.push_back(p);
  save();
}

void NodeLibraryPreferences::remove(const std::filesystem::path& path) {
  std::erase(files_, normalized_path(path));
  save();
}

void NodeLibraryPreferences::save() const {
  nlohmann::json j;
  j["node_libraries"] = nlohmann::json::array();
  for (const auto& p : files_) j["node_libraries"].push_back(p.string());
  try {
    write_text_atomically(file_, j.dump(2) + "\n");
  } catch (const std::exception&) {
    // Not stored: the libraries stay loaded for this session; nothing of the user's work is at stake.
  }
}

std::vector<std::string> load_editor_node_libraries(const NodeLibraryPreferences& preferences,
                                                    const std::vector<std::string>& explicit_files) {
  std::vector<std::filesystem::path> files;
  if (const char* folders = std::getenv("OROGEN_PLUGIN_PATH")) files = node_library_files(folders);
  files.insert(files.end(), preferences.files().begin(), preferences.files().end());
  files.insert(files.end(), explicit_files.begin(), explicit_files.end());
  return load_node_libraries(files);
}

}  // namespace orogen::editor
