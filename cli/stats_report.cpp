#include "cli/stats_report.h"

#include <sys/resource.h>
#include <unistd.h>

#include <fstream>

#include <nlohmann/json.hpp>

namespace orogen::cli {

std::size_t peak_memory_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::size_t>(usage.ru_maxrss) * 1024;  // ru_maxrss is in KiB on Linux
}

std::size_t resident_memory_bytes() {
  std::ifstream statm("/proc/self/statm");
  std::size_t total_pages = 0, resident_pages = 0;
  if (!(statm >> total_pages >> resident_pages)) return 0;
  return resident_pages * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
}

std::string stats_json(const EvalResult& result, const Graph* graph) {
  nlohmann::json nodes = nlohmann::json::object();
  std::map<std::string, int> counts{{"computed", 0}, {"cached", 0}, {"failed", 0}, {"skipped", 0}, {"cancelled", 0}};
  double node_ms = 0.0;
  std::size_t bytes = 0;
  for (const auto& [id, report] : result.nodes) {
    const std::string status(to_string(report.status));
    nlohmann::json entry = {{"status", status},
                            {"milliseconds", report.milliseconds},
                            {"output_bytes", report.output_bytes},
                            {"key", report.key.hex()}};
    if (!report.message.empty()) entry["message"] = report.message;
    nodes[id] = std::move(entry);
    ++counts[status];
    node_ms += report.milliseconds;
    bytes += report.output_bytes;
  }
  nlohmann::json totals = {{"nodes", result.nodes.size()},
                           {"node_milliseconds", node_ms},
                           {"wall_milliseconds", result.milliseconds},
                           {"output_bytes", bytes}};
  for (const auto& [status, n] : counts) totals[status] = n;
  // Report values (drainage metrics, ...) of the requested nodes, by node and port.
  nlohmann::json reports = nlohmann::json::object();
  for (const auto& [id, values] : result.outputs)
    for (std::size_t k = 0; k < values.size(); ++k)
      if (const auto* r = std::get_if<ReportPtr>(&values[k]); r && *r) {
        nlohmann::json parsed = nlohmann::json::parse((*r)->json, nullptr, false);
        const Node* node = graph ? graph->find(id) : nullptr;
        const std::string port =
            node && k < node->type->outputs.size() ? node->type->outputs[k].name : std::to_string(k);
        reports[id][port] = parsed.is_discarded() ? nlohmann::json((*r)->json) : parsed;
      }
  nlohmann::json doc = {{"nodes", nodes},
                        {"reports", reports},
                        {"totals", totals},
                        {"ok", result.ok()},
                        {"cancelled", result.cancelled},
                        {"peak_memory_bytes", peak_memory_bytes()}};
  return doc.dump(2) + "\n";
}

}  // namespace orogen::cli
