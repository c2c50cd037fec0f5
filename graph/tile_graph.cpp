#include "graph/tile_graph.h"

#include <map>

#include "graph/exec_context.h"

namespace orogen {
namespace {

// Filled at static initialisation (one thread), read-only afterwards.
struct Entry {
  TileGraphFactory factory;
  std::string conditions;
  std::vector<std::string> unlinked_inputs;
};

std::map<std::string, Entry>& factories() {
  static std::map<std::string, Entry> map;
  return map;
}

}  // namespace

bool register_tile_graph(const std::string& type, TileGraphFactory factory, std::string conditions,
                         std::vector<std::string> unlinked_inputs) {
  factories()[type] = {std::move(factory), std::move(conditions), std::move(unlinked_inputs)};
  return true;
}

const TileGraphFactory* find_tile_graph(const std::string& type) {
  const auto it = factories().find(type);
  return it == factories().end() ? nullptr : &it->second.factory;
}

std::unique_ptr<TileGraphAlgorithm> tile_graph_for(const std::string& type, const ParamView& params,
                                                   const Domain& whole) {
  const TileGraphFactory* factory = find_tile_graph(type);
  if (!factory) return nullptr;
  try {
    return (*factory)(params, whole);
  } catch (const NodeError&) {
    return nullptr;
  }
}

std::string tile_graph_conditions(const std::string& type) {
  const auto it = factories().find(type);
  return it == factories().end() ? std::string() : it->second.conditions;
}

std::vector<std::string> tile_graph_unlinked_inputs(const std::string& type) {
  const auto it = factories().find(type);
  return it == factories().end() ? std::vector<std::string>() : it->second.unlinked_inputs;
}

}  // namespace orogen
