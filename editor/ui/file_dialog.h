#pragma once
// A small ImGui file browser for Open, Save As and path parameters: the directory's folders and matching
// files, a path field, and the choice.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace orogen::editor {

class FileDialog {
 public:
  enum class Mode { Open, Save };

  // Shows the dialog from the next draw(). `extensions` like {".json"}; empty shows every file.
  void show(Mode mode, std::string title, const std::filesystem::path& start, std::vector<std::string> extensions);
  bool visible() const { return visible_ || pending_open_; }
  // Draws the dialog if shown; returns the chosen file once, when the user confirms.
  std::optional<std::filesystem::path> draw();

 private:
  void list_directory();
  bool matches(const std::filesystem::path& p) const;

  Mode mode_ = Mode::Open;
  std::string title_;
  std::vector<std::string> extensions_;
  std::filesystem::path dir_;
  std::string dir_text_, name_;
  std::vector<std::filesystem::path> dirs_, files_;
  std::string error_;
  bool visible_ = false, pending_open_ = false;
};

}  // namespace orogen::editor
