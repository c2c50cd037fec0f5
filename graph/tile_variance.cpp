#include "graph/tile_variance.h"

#include <map>

#include "graph/node_type.h"

namespace orogen {
namespace {

// Filled at static initialisation (one thread), read-only afterwards.
std::map<std::string, TileVariance>& registered() {
  static std::map<std::string, TileVariance> map;
  return map;
}

}  // namespace

bool register_tile_variance(const std::string& type, TileVariance why) {
  registered()[type] = std::move(why);
  return true;
}

std::string tile_variance(const NodeType& type, const std::vector<ParamValue>& params) {
  const auto it = registered().find(type.name);
  return it == registered().end() ? std::string() : it->second(ParamView(type, params));
}

}  // namespace orogen
