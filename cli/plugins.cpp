#include "cli/plugins.h"

#include <cstdlib>
#include <iostream>

#include "graph/node_library.h"

namespace orogen::cli {

bool load_plugins(const std::vector<std::string>& explicit_files) {
  if (const char* folders = std::getenv("OROGEN_PLUGIN_PATH"))
    for (const auto& error : load_node_libraries(node_library_files(folders)))
      std::cerr << "warning: " << error << " (from OROGEN_PLUGIN_PATH)\n";
  bool ok = true;
  for (const auto& file : explicit_files) {
    try {
      load_node_library(file);
    } catch (const std::exception& e) {
      std::cerr << "error: " << e.what() << "\n";
      ok = false;
    }
  }
  return ok;
}

}  // namespace orogen::cli
