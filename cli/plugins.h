#pragma once
// Node libraries for a command: those named with --plugin and those in the folders of OROGEN_PLUGIN_PATH.
// Loaded only by the commands that read the registry, so `orogen --help` never opens one.
#include <string>
#include <vector>

namespace orogen::cli {

// Loads the libraries of OROGEN_PLUGIN_PATH, then `explicit_files`. A library of the folders that fails is a
// warning on stderr (the other libraries still load); a --plugin library that fails is an error: returns false
// after printing why.
bool load_plugins(const std::vector<std::string>& explicit_files);

}  // namespace orogen::cli
