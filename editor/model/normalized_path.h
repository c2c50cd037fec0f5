#pragma once
// One spelling of a file path for the editor's lists (recent files, node libraries), so the same file added
// twice by different relative paths is one entry.
#include <filesystem>
#include <system_error>

namespace orogen::editor {

// Absolute (when the current directory can be read) and lexically normal.
inline std::filesystem::path normalized_path(const std::filesystem::path& p) {
  std::error_code ec;
  auto abs = std::filesystem::absolute(p, ec);
  return (ec ? p : abs).lexically_normal();
}

}  // namespace orogen::editor
