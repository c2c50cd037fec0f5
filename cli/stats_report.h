#pragma once
// The `--stats FILE.json` report: per-node status, time and output bytes, totals and peak memory.
#include <cstddef>
#include <string>

#include "evaluator/evaluator.h"

namespace orogen::cli {

// Peak resident memory of this process in bytes (getrusage).
std::size_t peak_memory_bytes();
// Resident memory of this process now, in bytes (/proc/self/statm; 0 where it cannot be read).
std::size_t resident_memory_bytes();
// With the graph, Report outputs are listed under "reports" by node and port name.
std::string stats_json(const EvalResult& result, const Graph* graph = nullptr);

}  // namespace orogen::cli
