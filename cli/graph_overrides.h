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
// Applies `--set` assignments and expands subgraph instances (graph/subgraph.h) in place: NODE.PARAM reaches a
// node's parameter or an instance's exposed parameter, INSTANCE/INNER.PARAM an inner node's parameter (applied
// after the expansion, so it wins over the exposed value) or a nested instance's exposed parameter. False, with
// `errors` filled, if anything failed.
bool expand_for_evaluation(Graph& graph, const std::vector<std::string>& assignments, std::vector<std::string>& errors);
// Parses "WxH" (e.g. 2048x2048) or a single number N for NxN; nullopt if malformed or out of [2, 65536].
std::optional<glm::ivec2> parse_resolution(const std::string& text);
// A finite number in [lo, hi] spelled in full (no trailing text; nan, inf and out-of-range values refused).
std::optional<double> parse_number(const std::string& text, double lo, double hi);
// A memory size in bytes: a number of MiB, or a number with a unit K, M, G or T (binary: KiB, MiB, ...),
// finite and at most 1 EiB; nullopt otherwise.
std::optional<std::uint64_t> parse_memory_size(const std::string& text);
// The sample counts `--resolution TEXT` asks for on a domain of `size` metres: "WxH", or a single number N
// for N samples along x and as many along y as keep the cells square. Cells must be square (the same
// spacing in x and y): anything else is refused with the resolution that would keep them square. nullopt
// and `error` set on failure.
std::optional<glm::ivec2> resolution_for(const std::string& text, glm::dvec2 size, std::string& error);

// Output-path parameters of writer nodes that the output rule refuses, and outputs that two writers would
// both write, as "node.param: reason".
std::vector<std::string> check_output_paths(const Graph& graph, const OutputPolicy& policy);

// What `orogen validate` checks beyond the file itself: the output paths (above) and the input files.
// An input file that does not exist is an error, unless a writer of the same graph writes it (then a
// warning: it may appear during the evaluation).
struct FileCheck {
  std::vector<std::string> errors, warnings;
};
FileCheck check_files(const Graph& graph, const OutputPolicy& policy);

}  // namespace orogen::cli
