#include "evaluator/memory_estimate.h"

#include <cstdio>
#include <exception>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace orogen {

std::uint64_t estimate_output_bytes(const NodeType& type, const Domain& domain) {
  const long double samples = static_cast<long double>(domain.resolution.x) * domain.resolution.y;
  long double per_sample = 4.0L;  // one working field
  for (const auto& out : type.outputs) {
    switch (out.type) {
      case PortType::Heightfield:
        per_sample += 4.0L;
        break;
      case PortType::Image:
        per_sample += 16.0L;
        break;
      case PortType::Mesh:
        per_sample += 160.0L;
        break;
      default:
        per_sample += 4.0L;
        break;
    }
  }
  const long double bytes = samples * per_sample;
  if (!(bytes < static_cast<long double>(std::numeric_limits<std::uint64_t>::max())))
    return std::numeric_limits<std::uint64_t>::max();
  return static_cast<std::uint64_t>(bytes);
}

std::uint64_t estimate_node_bytes(const CostQuery& query) {
  const std::uint64_t outputs = estimate_output_bytes(query.type, query.domain);
  if (!query.type.extra_bytes) return outputs;
  std::uint64_t extra = 0;
  try {
    extra = query.type.extra_bytes(query);
  } catch (const std::exception&) {
    extra = 0;
  }
  return extra > std::numeric_limits<std::uint64_t>::max() - outputs ? std::numeric_limits<std::uint64_t>::max()
                                                                     : outputs + extra;
}

std::string format_bytes(std::uint64_t bytes) {
  const char* units[] = {"B", "KB", "MB", "GB", "TB", "PB", "EB"};
  double v = static_cast<double>(bytes);
  int u = 0;
  while (v >= 1000.0 && u < 6) {
    v /= 1000.0;
    ++u;
  }
  char text[32];
  std::snprintf(text, sizeof text, u == 0 ? "%.0f %s" : "%.1f %s", v, units[u]);
  return text;
}

std::string memory_refusal(const NodeType& type, const Domain& domain, std::uint64_t need, std::uint64_t limit) {
  std::ostringstream s;
  s << "its type " << type.name << " needs at least " << format_bytes(need) << " (" << need << " bytes) at "
    << domain.resolution.x << "x" << domain.resolution.y << " samples; the memory limit is " << format_bytes(limit)
    << " (--max-memory)";
  return s.str();
}

std::uint64_t available_memory_bytes() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  std::uint64_t kb = 0;
  std::string unit;
  while (in >> key >> kb >> unit)
    if (key == "MemAvailable:") return kb * 1024;
  return 0;
}

}  // namespace orogen
