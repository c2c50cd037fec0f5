#include "graph/tile_graph.h"

#include <map>

namespace orogen {
namespace {

// Filled at static initialisation (one thread), read-only afterwards.
std::map<std::string, TileGraphFactory>& factories() {
  static std::map<std::string, TileGraphFactory> map;
  return map;
}

}  // namespace

bool register_tile_graph(const std::string& type, TileGraphFactory factory) {
  factories()[type] = std::move(factory);
  return true;
}

const TileGraphFactory* find_tile_graph(const std::string& type) {
  const auto it = factories().find(type);
  return it == factories().end() ? nullptr : &it->second;
}

}  // namespace orogen
