#pragma once
// Where the editor keeps its state between sessions (recent files, crash-recovery files):
// $XDG_STATE_HOME/orogen, or ~/.local/state/orogen when XDG_STATE_HOME is unset or not absolute.
#include <filesystem>

namespace orogen::editor {

std::filesystem::path default_state_dir();

}  // namespace orogen::editor
