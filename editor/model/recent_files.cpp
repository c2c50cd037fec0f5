#include "editor/model/recent_files.h"

#include <algorithm>
#include <fstream>

#include <nlohmann/json.hpp>

#include "editor/model/normalized_path.h"
#include "graph/atomic_file.h"

namespace orogen::editor {

RecentFiles::RecentFiles(std::filesystem::path file) : file_(std::move(file)) {
  std::ifstream in(file_);
  if (!in) return;
  try {
    const auto j = nlohmann::json::parse(in);
    for (const auto& entry : j.at("recent"))
      if (entry.is_string() && paths_.size() < kMax) paths_.emplace_back(entry.get<std::string>());
  } catch (const std::exception&) {
    paths_.clear();  // a damaged list is not worth an error dialog
  }
}

void RecentFiles::add(const std::filesystem::path& path) {
  const auto p = normalized_path(path);
  std::erase(paths_, p);
  paths_.insert(paths_.begin(), p);
  if (paths_.size() > kMax) paths_.resize(kMax);
  save();
}

void RecentFiles::remove(const std::filesystem::path& path) {
  std::erase(paths_, normalized_path(path));
  save();
}

void RecentFiles::clear() {
  paths_.clear();
  save();
}

void RecentFiles::save() const {
  nlohmann::json j;
  j["recent"] = nlohmann::json::array();
  for (const auto& p : paths_) j["recent"].push_back(p.string());
  try {
    write_text_atomically(file_, j.dump(2) + "\n");
  } catch (const std::exception&) {
    // The list is a convenience; failing to store it must not disturb the user's work.
  }
}

}  // namespace orogen::editor
