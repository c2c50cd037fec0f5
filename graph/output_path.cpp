#include "graph/output_path.h"

namespace orogen {

std::filesystem::path resolve_output_path(const OutputPolicy& policy, const std::string& graph_path) {
  namespace fs = std::filesystem;
  if (graph_path.empty()) throw OutputPathError("empty output path");
  const fs::path p(graph_path);
  if (policy.allow_any_path) return p.is_absolute() ? p : policy.output_dir / p;
  if (p.is_absolute() || p.has_root_name() || p.has_root_directory())
    throw OutputPathError("output path '" + graph_path +
                          "' is absolute; paths must stay inside the output directory (use --allow-any-path)");
  for (const auto& part : p)
    if (part == "..")
      throw OutputPathError("output path '" + graph_path +
                            "' climbs out of the output directory with '..' (use --allow-any-path)");
  return policy.output_dir / p.lexically_normal();
}

std::filesystem::path resolve_input_path(const std::filesystem::path& graph_dir, const std::string& graph_path) {
  const std::filesystem::path p(graph_path);
  if (p.is_absolute() || graph_dir.empty()) return p;
  return (graph_dir / p).lexically_normal();
}

}  // namespace orogen
