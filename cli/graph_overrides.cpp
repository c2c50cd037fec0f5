#include "cli/graph_overrides.h"

#include "cli/resolution_presets.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

#include "graph/graph_file.h"
#include "graph/json_util.h"
#include "graph/output_path.h"
#include "graph/subgraph.h"

namespace orogen::cli {

std::vector<std::string> apply_param_overrides(Graph& graph, const std::vector<std::string>& assignments) {
  std::vector<std::string> errors;
  for (const auto& a : assignments) {
    const auto eq = a.find('=');
    const auto dot = a.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot > eq) {
      errors.push_back("--set '" + a + "': expected NODE.PARAM=VALUE");
      continue;
    }
    const std::string node_id = a.substr(0, dot), name = a.substr(dot + 1, eq - dot - 1), text = a.substr(eq + 1);
    const Node* node = graph.find(node_id);
    if (!node) {
      std::vector<std::string> ids;
      for (const auto& n : graph.nodes()) ids.push_back(n.id);
      errors.push_back("--set '" + a + "': no node '" + node_id + "' in the graph" +
                       json_util::suggestion(node_id, ids));
      continue;
    }
    const ParamDecl* decl = node->type->find_param(name);
    if (!decl) {
      std::vector<std::string> names;
      for (const auto& p : node->type->params) names.push_back(p.name);
      errors.push_back("--set '" + a + "': node '" + node_id + "' (" + node->type->name + ") has no parameter '" +
                       name + "'" + json_util::suggestion(name, names));
      continue;
    }
    std::string why;
    auto value = param_from_text(text, *decl, why);
    if (!value) {
      errors.push_back("--set '" + a + "': " + why);
      continue;
    }
    graph.set_param(node_id, name, std::move(*value));
  }
  return errors;
}

bool expand_for_evaluation(Graph& graph, const std::vector<std::string>& assignments,
                           std::vector<std::string>& errors) {
  std::vector<std::string> outer, inner;
  for (const auto& a : assignments) {
    const auto slash = a.find('/'), dot = a.find('.');
    (slash != std::string::npos && (dot == std::string::npos || slash < dot) ? inner : outer).push_back(a);
  }
  auto more = apply_param_overrides(graph, outer);
  errors.insert(errors.end(), more.begin(), more.end());
  if (has_subgraphs(graph)) {
    try {
      ExpandedGraph expanded = expand_subgraphs(graph);
      // INSTANCE/NESTED.PARAM names an exposed parameter of a nested instance, which only exists before its
      // expansion: expand again with those values.
      InstanceOverrides nested;
      std::vector<std::string> plain;
      for (const auto& a : inner) {
        const auto eq = a.find('='), dot = a.find('.');
        const std::string node_id = a.substr(0, dot);
        const auto type = expanded.types.find(node_id);
        if (eq == std::string::npos || dot == std::string::npos || dot > eq || type == expanded.types.end()) {
          plain.push_back(a);
          continue;
        }
        const std::string name = a.substr(dot + 1, eq - dot - 1);
        const ParamDecl* decl = type->second->find_param(name);
        if (!decl) {
          std::vector<std::string> names;
          for (const auto& p : type->second->params) names.push_back(p.name);
          errors.push_back("--set '" + a + "': subgraph instance '" + node_id + "' has no parameter '" + name + "'" +
                           json_util::suggestion(name, names));
          continue;
        }
        std::string why;
        if (auto value = param_from_text(a.substr(eq + 1), *decl, why))
          nested[node_id][name] = std::move(*value);
        else
          errors.push_back("--set '" + a + "': " + why);
      }
      if (!nested.empty()) expanded = expand_subgraphs(graph, &nested);
      graph = std::move(expanded.graph);
      inner = std::move(plain);
    } catch (const GraphError& e) {
      errors.push_back(e.what());
      return false;
    }
  }
  more = apply_param_overrides(graph, inner);
  errors.insert(errors.end(), more.begin(), more.end());
  return errors.empty();
}

std::optional<glm::ivec2> parse_resolution(const std::string& text) {
  auto parse_int = [](std::string_view s) -> std::optional<int> {
    int v = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || end != s.data() + s.size() || v < 2 || v > 65536) return std::nullopt;
    return v;
  };
  const auto x = text.find_first_of("xX");
  if (x == std::string::npos) {
    auto n = parse_int(text);
    if (!n) return std::nullopt;
    return glm::ivec2(*n, *n);
  }
  auto w = parse_int(std::string_view(text).substr(0, x));
  auto h = parse_int(std::string_view(text).substr(x + 1));
  if (!w || !h) return std::nullopt;
  return glm::ivec2(*w, *h);
}

std::optional<double> parse_number(const std::string& text, double lo, double hi) {
  if (text.empty() || text.size() > 64) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v) || v < lo || v > hi)
    return std::nullopt;
  return v;
}

std::optional<std::uint64_t> parse_memory_size(const std::string& text) {
  std::string number = text;
  double unit = 1024.0 * 1024.0;
  if (!number.empty()) {
    std::string suffix;
    while (!number.empty() && std::isalpha(static_cast<unsigned char>(number.back()))) {
      suffix.insert(suffix.begin(), static_cast<char>(std::toupper(static_cast<unsigned char>(number.back()))));
      number.pop_back();
    }
    if (suffix == "K" || suffix == "KB" || suffix == "KIB")
      unit = 1024.0;
    else if (suffix == "M" || suffix == "MB" || suffix == "MIB")
      unit = 1024.0 * 1024.0;
    else if (suffix == "G" || suffix == "GB" || suffix == "GIB")
      unit = 1024.0 * 1024.0 * 1024.0;
    else if (suffix == "T" || suffix == "TB" || suffix == "TIB")
      unit = 1024.0 * 1024.0 * 1024.0 * 1024.0;
    else if (!suffix.empty())
      return std::nullopt;
  }
  const auto v = parse_number(number, 0.0, std::ldexp(1.0, 60) / unit);
  if (!v) return std::nullopt;
  return static_cast<std::uint64_t>(*v * unit);
}

std::optional<glm::ivec2> resolution_for(const std::string& text, glm::dvec2 size, std::string& error) {
  const auto preset = resolution_preset(text);  // an engine's size by name: samples along x
  auto r = preset ? std::optional<glm::ivec2>(glm::ivec2(*preset, *preset)) : parse_resolution(text);
  if (!r) {
    error = "--resolution '" + text + "': expected WxH with sides in [2, 65536], a single number, or an engine's " +
            "size by name (" + resolution_preset_names() + ")";
    return std::nullopt;
  }
  const bool single = preset || text.find_first_of("xX") == std::string::npos;
  if (single && size.x > 0.0) {
    // N along x, and along y whatever keeps the cells square.
    const double rows = size.y / (size.x / (r->x - 1)) + 1.0;
    r->y = static_cast<int>(std::clamp(std::llround(rows), 2LL, 65536LL));
  }
  const double sx = size.x / (r->x - 1), sy = size.y / (r->y - 1);
  if (std::abs(sx - sy) <= 1e-9 * std::max(sx, sy)) return r;
  std::ostringstream s;
  s << "--resolution " << text << " on the graph's " << size.x << " x " << size.y << " m domain gives cells of " << sx
    << " m x " << sy << " m; cells must be square (the same spacing in x and y)";
  const double rows = size.y / sx + 1.0;
  if (std::abs(rows - std::round(rows)) < 1e-6 && rows >= 2.0 && rows <= 65536.0)
    s << ": use " << r->x << "x" << std::llround(rows) << " (or just " << r->x << ")";
  else
    s << ": choose W and H with (W - 1) / (H - 1) = " << size.x << " / " << size.y
      << ", or change the domain's size in the graph";
  error = s.str();
  return std::nullopt;
}

namespace {

// What a path designates on the real file system, to tell whether two paths name one file: its directory with
// every symbolic link resolved (as far as it exists; "out/same -> ." makes "out/same/a" and "out/a" one file)
// plus its name. The name itself is not resolved: writers rename over it, replacing a link, not its target.
std::string file_identity(const std::filesystem::path& p) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path absolute = fs::absolute(p, ec).lexically_normal();
  if (ec) return p.lexically_normal().generic_string();
  const fs::path dir = fs::weakly_canonical(absolute.parent_path(), ec);
  return ((ec ? absolute.parent_path() : dir) / absolute.filename()).generic_string();
}

// Every output file of the graph's writers: identity -> "node.param", with the refused ones in `errors`.
std::map<std::string, std::string> output_files(const Graph& graph, const OutputPolicy& policy,
                                                std::vector<std::string>& errors) {
  std::map<std::string, std::string> files;
  for (const auto& node : graph.nodes()) {
    for (const auto& decl : node.type->params) {
      if (!decl.output_file) continue;
      const auto& value = std::get<std::string>(graph.param(node.id, decl.name));
      const std::string where = node.id + "." + decl.name;
      try {
        const auto file = resolve_output_path(policy, value);
        const auto [it, added] = files.emplace(file_identity(file), where);
        if (!added)
          errors.push_back(where + ": '" + value + "' is also written by " + it->second +
                           "; two writers to one file would overwrite each other");
      } catch (const OutputPathError& e) {
        errors.push_back(where + ": " + e.what());
      }
    }
  }
  return files;
}

}  // namespace

std::vector<std::string> check_output_paths(const Graph& graph, const OutputPolicy& policy) {
  std::vector<std::string> errors;
  output_files(graph, policy, errors);
  return errors;
}

FileCheck check_files(const Graph& graph, const OutputPolicy& policy) {
  FileCheck check;
  const auto outputs = output_files(graph, policy, check.errors);
  for (const auto& node : graph.nodes()) {
    for (const auto& decl : node.type->params) {
      if (decl.type != ParamType::Path || decl.output_file) continue;
      const auto& value = std::get<std::string>(graph.param(node.id, decl.name));
      const std::string where = node.id + "." + decl.name;
      if (value.empty()) {
        check.errors.push_back(where + ": no file given");
        continue;
      }
      const auto file = resolve_input_path(graph.directory, value);
      std::error_code ec;
      if (std::filesystem::is_regular_file(file, ec)) continue;
      const auto writer = outputs.find(file_identity(file));
      if (writer != outputs.end()) {
        check.warnings.push_back(where + ": '" + file.string() + "' does not exist yet; " + writer->second +
                                 " writes it during the evaluation (it may be read before it is written)");
      } else {
        check.errors.push_back(where + ": input file '" + file.string() + "' does not exist" +
                               (std::filesystem::path(value).is_relative()
                                    ? " (relative input paths resolve against the graph file's directory)"
                                    : ""));
      }
    }
  }
  return check;
}

}  // namespace orogen::cli
