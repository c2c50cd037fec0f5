#pragma once
// The list of recently opened or saved graph files (File > Recent), newest first, kept in the state
// directory as JSON.
#include <filesystem>
#include <vector>

namespace orogen::editor {

class RecentFiles {
 public:
  static constexpr std::size_t kMax = 10;

  // Reads `file` if it exists (a missing or unreadable list is an empty list).
  explicit RecentFiles(std::filesystem::path file);

  const std::vector<std::filesystem::path>& paths() const { return paths_; }
  // Moves `path` (made absolute) to the front, dropping duplicates and the oldest beyond kMax; saves.
  void add(const std::filesystem::path& path);
  void remove(const std::filesystem::path& path);
  void clear();

 private:
  void save() const;
  std::filesystem::path file_;
  std::vector<std::filesystem::path> paths_;
};

}  // namespace orogen::editor
