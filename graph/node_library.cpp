#include "graph/node_library.h"

#include <dlfcn.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <mutex>

#include "graph/registry.h"
#include "orogen/version.h"

namespace orogen {
namespace {

std::mutex& loader_mutex() {
  static std::mutex m;
  return m;
}

std::vector<NodeLibrary>& loaded() {
  static std::vector<NodeLibrary> libraries;
  return libraries;
}

std::string quoted(const std::filesystem::path& p) { return "'" + p.string() + "'"; }

std::string field(std::string_view stamp, std::string_view key) {
  const std::string needle = ";" + std::string(key) + "=";
  const auto at = stamp.find(needle);
  if (at == std::string_view::npos) return {};
  const auto start = at + needle.size();
  const auto end = stamp.find(';', start);
  return std::string(stamp.substr(start, end == std::string_view::npos ? end : end - start));
}

}  // namespace

NodeLibraryStamp read_node_library_stamp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw NodeLibraryError("node library " + quoted(path) + ": cannot be read (missing or not a file)");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto at = bytes.find(kNodeLibraryStampMarker);
  if (at == std::string::npos)
    throw NodeLibraryError("node library " + quoted(path) +
                           ": not an Orogen node library (no stamp: build it with orogen_add_node_library)");
  const auto end = bytes.find('\0', at);
  const std::string_view stamp(bytes.data() + at, (end == std::string::npos ? bytes.size() : end) - at);
  const std::string_view body = stamp.substr(kNodeLibraryStampMarker.size() - 1);  // from the ';'
  NodeLibraryStamp s;
  s.name = field(body, "name");
  s.version = field(body, "version");
  const auto abi = field(body, "abi");
  s.abi = abi.empty() ? 0 : std::atoi(abi.c_str());
  if (s.name.empty() || s.version.empty() || s.abi <= 0)
    throw NodeLibraryError("node library " + quoted(path) + ": damaged stamp '" + std::string(stamp) + "'");
  return s;
}

NodeLibrary load_node_library(const std::filesystem::path& path) {
  std::lock_guard lock(loader_mutex());
  std::error_code ec;
  const auto canonical = std::filesystem::weakly_canonical(path, ec);
  for (const auto& lib : loaded())
    if (lib.path == (ec ? path : canonical)) return lib;

  const auto stamp = read_node_library_stamp(path);
  if (stamp.version != OROGEN_SDK_VERSION || stamp.abi != OROGEN_NODE_ABI)
    throw NodeLibraryError("node library " + quoted(path) + " ('" + stamp.name + "') was built against Orogen " +
                           stamp.version + " (node ABI " + std::to_string(stamp.abi) + "), but this is Orogen " +
                           OROGEN_SDK_VERSION + " (node ABI " + std::to_string(OROGEN_NODE_ABI) +
                           "): rebuild it against this version's SDK");
  for (const auto& lib : loaded())
    if (lib.name == stamp.name)
      throw NodeLibraryError("node library " + quoted(path) + ": a library named '" + stamp.name +
                             "' is already loaded from " + quoted(lib.path));

  auto& registry = NodeRegistry::instance();
  NodeRegistry::Staging staging;
  registry.set_staging(&staging);
  // RTLD_NOW: an unresolved symbol (a function the SDK does not provide) is an error here, not a crash later.
  // RTLD_LOCAL: the library's own symbols stay out of the global scope, so two libraries cannot clash.
  // The path gets a directory part so that dlopen does not search the library path for a bare name.
  const auto open_path = path.has_parent_path() ? path : std::filesystem::path(".") / path;
  void* handle = dlopen(open_path.c_str(), RTLD_NOW | RTLD_LOCAL);
  registry.set_staging(nullptr);
  if (!handle) {
    const char* why = dlerror();
    throw NodeLibraryError("node library " + quoted(path) + ": cannot be opened: " + (why ? why : "unknown error"));
  }

  std::vector<std::string> errors = staging.errors;
  for (std::size_t i = 0; i < staging.types.size(); ++i) {
    const auto& t = staging.types[i];
    try {
      check_declaration(t);
    } catch (const std::exception& e) {
      errors.push_back("node type '" + t.name + "': " + e.what());
    }
    if (const NodeType* existing = registry.find(t.name))
      errors.push_back("node type '" + t.name + "' already exists (" +
                       (existing->library.empty() ? std::string("built into Orogen")
                                                  : "from node library '" + existing->library + "'") +
                       ")");
    for (std::size_t j = 0; j < i; ++j)
      if (staging.types[j].name == t.name) errors.push_back("node type '" + t.name + "' is declared twice");
  }
  if (staging.types.empty() && errors.empty()) errors.push_back("it declares no node type");
  if (!errors.empty()) {
    // Nothing of the library is registered, so nothing refers to its code any more.
    staging.types.clear();
    dlclose(handle);
    std::string message = "node library " + quoted(path) + " ('" + stamp.name + "') was not loaded:";
    for (const auto& e : errors) message += "\n  " + e;
    throw NodeLibraryError(message);
  }

  // The handle stays open for the life of the process: the registered types hold its code.
  NodeLibrary lib{stamp.name, ec ? path : canonical, {}};
  for (auto& t : staging.types) {
    t.library = stamp.name;
    lib.types.push_back(t.name);
    registry.add(std::move(t));
  }
  loaded().push_back(lib);
  return lib;
}

std::vector<NodeLibrary> loaded_node_libraries() {
  std::lock_guard lock(loader_mutex());
  return loaded();
}

std::vector<std::filesystem::path> node_library_files(std::string_view folder_list) {
  std::vector<std::filesystem::path> files;
  std::size_t start = 0;
  while (start <= folder_list.size()) {
    const auto end = std::min(folder_list.find(':', start), folder_list.size());
    const std::filesystem::path folder(std::string(folder_list.substr(start, end - start)));
    start = end + 1;
    std::error_code ec;
    if (folder.empty() || !std::filesystem::is_directory(folder, ec)) continue;
    std::vector<std::filesystem::path> found;
    for (const auto& entry : std::filesystem::directory_iterator(folder, ec))
      if (entry.path().extension() == ".so" && entry.is_regular_file(ec)) found.push_back(entry.path());
    std::sort(found.begin(), found.end());
    files.insert(files.end(), found.begin(), found.end());
  }
  return files;
}

std::vector<std::string> load_node_libraries(const std::vector<std::filesystem::path>& files) {
  std::vector<std::string> errors;
  for (const auto& f : files) {
    try {
      load_node_library(f);
    } catch (const std::exception& e) {
      errors.push_back(e.what());
    }
  }
  return errors;
}

}  // namespace orogen
