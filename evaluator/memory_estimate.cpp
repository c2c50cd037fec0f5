#include "evaluator/memory_estimate.h"

#include <cstdio>
#include <algorithm>
#include <exception>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

namespace orogen {

namespace {

bool is_raster(PortType t) { return t == PortType::Heightfield || t == PortType::Image; }

std::uint64_t saturate(long double bytes) {
  if (!(bytes < static_cast<long double>(std::numeric_limits<std::uint64_t>::max())))
    return std::numeric_limits<std::uint64_t>::max();
  return static_cast<std::uint64_t>(bytes);
}

std::uint64_t add_saturating(std::uint64_t a, std::uint64_t b) {
  return b > std::numeric_limits<std::uint64_t>::max() - a ? std::numeric_limits<std::uint64_t>::max() : a + b;
}

}  // namespace

std::uint64_t estimate_output_bytes(const NodeType& type, const Domain& domain) {
  const long double samples = static_cast<long double>(domain.resolution.x) * domain.resolution.y;
  bool raster_output = false;
  long double per_sample = 0.0L;
  for (const auto& out : type.outputs) {
    raster_output = raster_output || is_raster(out.type);
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
  // Values on a lattice of their own or of no lattice (a mesh of rocks, a word): sized by the node's
  // declaration (extra_bytes) and its inputs, not by the domain.
  if (type.domain_independent || type.own_lattice) return 0;
  // One working field, for nodes that make rasters; a writer holds a block of rows at least.
  if (raster_output || type.writes_files || type.outputs.empty()) per_sample += 4.0L;
  return saturate(samples * per_sample);
}

std::uint64_t estimate_node_bytes(const CostQuery& query) {
  std::uint64_t base = estimate_output_bytes(query.type, query.domain);
  if (query.inputs && !query.type.writes_files) {
    // With the inputs known, values that are not rasters (points, curves, meshes, scenes ...) are sized by the
    // inputs they derive from, not by the domain: each such output about as large as the inputs of its type
    // together (a scene: its instances, the points), or as the node's declaration says when it makes one type
    // from another (a tree mesh from its skeleton's curves).
    bool value_inputs = false;
    for (std::size_t k = 0; k < query.inputs->size() && k < query.type.inputs.size(); ++k)
      value_inputs = value_inputs || (has_value((*query.inputs)[k]) && !is_raster(query.type.inputs[k].type));
    if (value_inputs) {
      const long double samples = static_cast<long double>(query.domain.resolution.x) * query.domain.resolution.y;
      for (const auto& out : query.type.outputs) {
        if (is_raster(out.type)) continue;
        if (!query.type.domain_independent && !query.type.own_lattice) {
          const long double by_domain = samples * (out.type == PortType::Mesh ? 160.0L : 4.0L);
          base = base - std::min<std::uint64_t>(base, saturate(by_domain));
        }
        const PortType source = out.type == PortType::Scene ? PortType::Points : out.type;
        for (std::size_t k = 0; k < query.inputs->size() && k < query.type.inputs.size(); ++k)
          if (query.type.inputs[k].type == source && has_value((*query.inputs)[k]))
            base = add_saturating(base, byte_size((*query.inputs)[k]));
      }
    }
  }
  if (!query.type.extra_bytes) return base;
  std::uint64_t extra = 0;
  try {
    extra = query.type.extra_bytes(query);
  } catch (const std::exception&) {
    extra = 0;
  }
  return add_saturating(base, extra);
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
