#include "graph/output_path.h"

#include <cstdio>
#include <system_error>

namespace orogen {

std::string check_path_text(const std::string& text) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c == 0x7f) {
      char code[8];
      std::snprintf(code, sizeof code, "0x%02x", c);
      return std::string("contains the control character ") + code + " at byte " + std::to_string(i) +
             "; file paths must be printable";
    }
  }
  return {};
}

bool path_is_within(const std::filesystem::path& real, const std::filesystem::path& root) {
  auto r = root.begin();
  auto p = real.begin();
  for (; r != root.end(); ++r, ++p) {
    if (r->empty()) continue;  // a trailing separator
    if (p == real.end() || *p != *r) return false;
  }
  return true;
}

void prepare_output_directory(const OutputPolicy& policy, const std::filesystem::path& target) {
  namespace fs = std::filesystem;
  const fs::path parent = target.parent_path();
  if (policy.allow_any_path) {
    if (!parent.empty()) fs::create_directories(parent);
    return;
  }
  const fs::path root_dir = policy.output_dir.empty() ? fs::path(".") : policy.output_dir;
  fs::create_directories(root_dir);
  const fs::path root = fs::canonical(root_dir);
  // Walk from the output directory down to the parent, one component at a time, so no directory is created
  // behind a link that leaves the output directory.
  // Both sides normalised, without a trailing separator ("out/" and "./out" name the same directory).
  auto normal = [](const fs::path& p) {
    fs::path n = (p.empty() ? fs::path(".") : p).lexically_normal();
    if (n.filename().empty() && n.has_parent_path() && n != n.root_path()) n = n.parent_path();
    return n;
  };
  const fs::path relative = normal(parent).lexically_relative(normal(root_dir));
  fs::path at = root_dir;
  auto refuse = [&](const fs::path& where) {
    throw OutputPathError("output path '" + target.string() + "' leaves the output directory through the link '" +
                          where.string() + "' (use --allow-any-path)");
  };
  if (!relative.empty() && relative != ".") {
    for (const auto& part : relative) {
      if (part.empty() || part == ".") continue;
      if (part == "..") refuse(at / part);
      at /= part;
      std::error_code ec;
      const auto status = fs::symlink_status(at, ec);
      if (fs::is_symlink(status)) {
        const fs::path real = fs::weakly_canonical(at);
        if (!path_is_within(real, root)) refuse(at);
      }
      if (!fs::exists(at)) fs::create_directory(at);
    }
  }
  // The final check on the real path (another process could have swapped a directory for a link meanwhile;
  // this narrows the window to the write itself).
  const fs::path real_parent = fs::canonical(parent.empty() ? root_dir : parent);
  if (!path_is_within(real_parent, root)) refuse(parent);
  // (A link at the target itself is harmless: the rename replaces the link, never what it points to.)
}

std::filesystem::path resolve_output_path(const OutputPolicy& policy, const std::string& graph_path) {
  namespace fs = std::filesystem;
  if (graph_path.empty()) throw OutputPathError("empty output path");
  if (auto why = check_path_text(graph_path); !why.empty())
    throw OutputPathError("output path '" + graph_path.substr(0, graph_path.find('\0')) + "' " + why);
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
