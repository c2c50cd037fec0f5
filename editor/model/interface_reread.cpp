#include "editor/model/interface_reread.h"

#include <memory>

#include "graph/subgraph.h"

namespace orogen::editor {

LoadResult reread_with_interface(const Graph& asset, const nlohmann::json& interface_json, bool keep_partial) {
  Graph next = asset;
  auto text_only = std::make_shared<SubgraphInterface>(*asset.interface);
  text_only->json_text = interface_json.dump();
  next.interface = text_only;
  LoadOptions options;
  options.directory = asset.directory;
  options.allow_unconnected_inputs = true;
  options.keep_partial = keep_partial;
  return parse_graph(serialize_graph(next), options);
}

}  // namespace orogen::editor
