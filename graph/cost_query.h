#pragma once
// What a node type may read to say how much memory it needs beyond what its output types and the domain tell
// (evaluator/memory_estimate.h): images of many channels, words grown by rewriting, files read whole, values
// sized by their inputs. Asked twice: before anything runs (`inputs` null: estimate from the parameters, or
// from what upstream nodes can produce at most) and again just before the node runs (its inputs known).
#include <cstdint>
#include <filesystem>
#include <string_view>
#include <vector>

#include "graph/domain.h"
#include "graph/node_type.h"
#include "graph/port_value.h"

namespace orogen {

struct CostQuery {
  const NodeType& type;
  const Domain& domain;
  ParamView params;
  const std::vector<PortValue>* inputs = nullptr;  // null before the inputs exist
  std::filesystem::path input_dir;                 // where relative paths in parameters resolve
  std::vector<bool> linked;  // before the inputs exist: which inputs have a link (empty: unknown, all)

  // The value on input `name`, or null when it is not connected or not known yet.
  const PortValue* input(std::string_view name) const {
    const int k = type.input_index(name);
    if (!inputs || k < 0 || static_cast<std::size_t>(k) >= inputs->size()) return nullptr;
    const PortValue& v = (*inputs)[static_cast<std::size_t>(k)];
    return has_value(v) ? &v : nullptr;
  }
  // Whether input `name` receives a value: it holds one, or (before the inputs exist) it has a link.
  bool is_linked(std::string_view name) const {
    if (inputs) return input(name) != nullptr;
    const int k = type.input_index(name);
    if (k < 0) return false;
    const auto index = static_cast<std::size_t>(k);
    return linked.empty() || (index < linked.size() && linked[index]);
  }
};

// `bytes` per sample of the query's domain (working fields a node holds beyond its outputs), saturating.
inline std::uint64_t per_sample_bytes(const CostQuery& q, double bytes) {
  const double total = static_cast<double>(q.domain.resolution.x) * q.domain.resolution.y * bytes;
  return total < 1.8e19 ? static_cast<std::uint64_t>(total) : ~std::uint64_t{0};
}

// `bytes` for each of `count` items (cells, points, triangles) counted from parameters, saturating.
inline std::uint64_t per_item_bytes(double count, double bytes) {
  const double total = count * bytes;
  return total >= 0.0 && total < 1.8e19 ? static_cast<std::uint64_t>(total) : (total >= 0.0 ? ~std::uint64_t{0} : 0);
}

// The bytes held by the value on input `name` (0 when it is not known).
inline std::uint64_t input_bytes(const CostQuery& q, std::string_view name) {
  const PortValue* v = q.input(name);
  return v ? byte_size(*v) : 0;
}

}  // namespace orogen
