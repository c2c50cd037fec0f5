#pragma once
// The node libraries the editor loads at every start (Preferences > Node Libraries), kept in the state
// directory as JSON, and the loading itself: OROGEN_PLUGIN_PATH, the preferences, then --plugin. A library
// that fails is reported, never fatal: the editor starts with the others.
#include <filesystem>
#include <string>
#include <vector>

namespace orogen::editor {

class NodeLibraryPreferences {
 public:
  // Reads `file` if it exists (a missing or damaged list is an empty list).
  explicit NodeLibraryPreferences(std::filesystem::path file);

  const std::vector<std::filesystem::path>& files() const { return files_; }
  // Adds `path` (made absolute) unless listed; saves.
  void add(const std::filesystem::path& path);
  void remove(const std::filesystem::path& path);

 private:
  void save() const;
  std::filesystem::path file_;
  std::vector<std::filesystem::path> files_;
};

// Loads the libraries of OROGEN_PLUGIN_PATH, of the preferences and `explicit_files`, in that order; returns
// one message per library that failed.
std::vector<std::string> load_editor_node_libraries(const NodeLibraryPreferences& preferences,
                                                    const std::vector<std::string>& explicit_files);

}  // namespace orogen::editor
