#pragma once
// Node libraries: shared libraries of node types, built against the installed SDK with
// orogen_add_node_library and loaded at run time (`orogen --plugin`, OROGEN_PLUGIN_PATH, the editor's
// preferences). See docs/plugins.md.
//
// A library's OROGEN_NODE declarations run inside the host: the host's executable exports its symbols, so the
// library binds to the host's one NodeRegistry (it links no copy of Orogen). Before the file is opened its
// stamp (sdk/node_library_stamp.cpp) is read from the file: a library built against another version of
// Orogen is refused without running any of its code.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace orogen {

struct NodeLibraryError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct NodeLibrary {
  std::string name;                // the library's name (orogen_add_node_library's target), carried by its types
  std::filesystem::path path;      // the file it was loaded from
  std::vector<std::string> types;  // the node types it registered
};

// What a library's stamp says: "orogen-node-library-stamp;name=N;version=V;abi=A;".
struct NodeLibraryStamp {
  std::string name, version;
  int abi = 0;
};
inline constexpr std::string_view kNodeLibraryStampMarker = "orogen-node-library-stamp;";

// The stamp in the file at `path`; throws NodeLibraryError when it cannot be read or carries none.
NodeLibraryStamp read_node_library_stamp(const std::filesystem::path& path);

// Opens the library at `path` and registers its node types, all or none. Throws NodeLibraryError naming the file
// when it cannot be read, has no stamp or one of another version or ABI (both versions named), cannot be
// opened (the loader's message), declares a type that is invalid, throws or already exists. A file already
// loaded (the same canonical path) is not loaded twice: its entry is returned.
NodeLibrary load_node_library(const std::filesystem::path& path);

// The libraries loaded so far, in load order.
std::vector<NodeLibrary> loaded_node_libraries();

// The node library files in a list of folders separated by ':' (OROGEN_PLUGIN_PATH): every "*.so" in each,
// sorted by name within a folder; an empty entry or a missing folder is skipped.
std::vector<std::filesystem::path> node_library_files(std::string_view folder_list);

// Loads each file, collecting the errors ("<file>: why") instead of stopping at the first.
std::vector<std::string> load_node_libraries(const std::vector<std::filesystem::path>& files);

}  // namespace orogen
