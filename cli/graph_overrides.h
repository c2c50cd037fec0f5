#pragma once
// Command-line changes to a loaded graph: `--set NODE.PARAM=VALUE` and `--resolution WxH`.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/graph.h"
#include "graph/output_path.h"

namespace orogen::cli {

// Applies every assignment; returns one message per assignment that could not be applied.
std::vector<std::string> apply_param_overrides(Graph& graph, const std::vector<std::string>& assignments);
// Parses "WxH" (e.g. 2048x2048) or a single number N for NxN; nullopt if malformed or out of [2, 65536].
std::optional<glm::ivec2> parse_resolution(const std::string& text);
// A finite number in [lo, hi] spelled in full (no trailing text; nan, inf and out-of-range values refused).
std::optional<double> parse_number(const std::string& text, double lo, double hi);
// A memory size in bytes: a number of MiB, or a number with a unit K, M, G or T (binary: KiB, MiB, ...),
// finite and at most 1 EiB; nullopt otherwise.
std::optional<std::uint64_t> parse_memory_size(const std::string& text);
// Output-path parameters of writer nodes that the output rule refuses, as "node.param: reason".
std::vector<std::string> check_output_paths(const Graph& graph, const OutputPolicy& policy);

}  // namespace orogen::cli
