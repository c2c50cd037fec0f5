#pragma once
// Where writer nodes may write. A graph file from someone else is data, not a program: its output paths
// resolve inside the output directory, and absolute paths or paths climbing out with ".." are refused
// unless explicitly allowed.
#include <filesystem>
#include <stdexcept>
#include <string>

namespace orogen {

struct OutputPolicy {
  std::filesystem::path output_dir = "out";
  bool allow_any_path = false;
};

struct OutputPathError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The file a graph path refers to under `policy`; throws OutputPathError when the rule refuses it.
std::filesystem::path resolve_output_path(const OutputPolicy& policy, const std::string& graph_path);

// Creates the directories leading to `target` (a path from resolve_output_path) and checks, on the real file
// system, that they lie inside the output directory: a symbolic link inside it that points elsewhere is
// refused unless policy.allow_any_path. Throws OutputPathError (refused) or std::filesystem_error.
void prepare_output_directory(const OutputPolicy& policy, const std::filesystem::path& target);

// True if `real` (a canonical path) is `root` (canonical) or lies below it.
bool path_is_within(const std::filesystem::path& real, const std::filesystem::path& root);

// Empty if `text` may be a file path in a graph, else why not (control characters, NUL).
std::string check_path_text(const std::string& text);

// The file an input path of a graph designates: absolute paths as they are, relative ones against the
// directory of the graph file (`graph_dir`; empty: the current directory). Unlike outputs, inputs may lie
// anywhere: reading is not a risk to the user's files.
std::filesystem::path resolve_input_path(const std::filesystem::path& graph_dir, const std::string& graph_path);

}  // namespace orogen
