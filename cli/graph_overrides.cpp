#include "cli/graph_overrides.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include <charconv>

#include "graph/graph_file.h"
#include "graph/output_path.h"

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
      errors.push_back("--set '" + a + "': no node '" + node_id + "' in the graph");
      continue;
    }
    const ParamDecl* decl = node->type->find_param(name);
    if (!decl) {
      errors.push_back("--set '" + a + "': node '" + node_id + "' (" + node->type->name + ") has no parameter '" + name + "'");
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
  if (end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v) || v < lo || v > hi) return std::nullopt;
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
    if (suffix == "K" || suffix == "KB" || suffix == "KIB") unit = 1024.0;
    else if (suffix == "M" || suffix == "MB" || suffix == "MIB") unit = 1024.0 * 1024.0;
    else if (suffix == "G" || suffix == "GB" || suffix == "GIB") unit = 1024.0 * 1024.0 * 1024.0;
    else if (suffix == "T" || suffix == "TB" || suffix == "TIB") unit = 1024.0 * 1024.0 * 1024.0 * 1024.0;
    else if (!suffix.empty()) return std::nullopt;
  }
  const auto v = parse_number(number, 0.0, std::ldexp(1.0, 60) / unit);
  if (!v) return std::nullopt;
  return static_cast<std::uint64_t>(*v * unit);
}

std::vector<std::string> check_output_paths(const Graph& graph, const OutputPolicy& policy) {
  std::vector<std::string> errors;
  for (const auto& node : graph.nodes()) {
    for (const auto& decl : node.type->params) {
      if (!decl.output_file) continue;
      const auto& value = std::get<std::string>(graph.param(node.id, decl.name));
      try {
        resolve_output_path(policy, value);
      } catch (const OutputPathError& e) {
        errors.push_back(node.id + "." + decl.name + ": " + e.what());
      }
    }
  }
  return errors;
}

}  // namespace orogen::cli
