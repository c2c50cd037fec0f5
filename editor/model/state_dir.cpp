#include "editor/model/state_dir.h"

#include <cstdlib>

namespace orogen::editor {

std::filesystem::path default_state_dir() {
  // The XDG base directory spec says relative paths are invalid and must be ignored.
  if (const char* xdg = std::getenv("XDG_STATE_HOME"); xdg && *xdg && std::filesystem::path(xdg).is_absolute())
    return std::filesystem::path(xdg) / "orogen";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::filesystem::path(home) / ".local" / "state" / "orogen";
  return std::filesystem::temp_directory_path() / "orogen-state";
}

}  // namespace orogen::editor
