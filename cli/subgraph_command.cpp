// `orogen subgraph extract G.json --nodes a,b,c -o asset.orogen-subgraph.json`: a selection of nodes becomes a
// subgraph asset and the graph is rewritten to use an instance of it (graph/subgraph_extract.h).
// `orogen subgraph make-unique G.json --node ID [-o OUT.json]`: the instance gets an embedded copy of its asset
// (graph/subgraph_unique.h).
#include <filesystem>
#include <iostream>

#include "cli/commands.h"
#include "graph/atomic_file.h"
#include "graph/graph_file.h"
#include "graph/subgraph.h"
#include "graph/subgraph_extract.h"
#include "graph/subgraph_unique.h"

namespace orogen::cli {

namespace fs = std::filesystem;

int run_subgraph_extract(const ExtractCommand& cmd) {
  const LoadResult loaded = load_graph_file(cmd.graph_file);
  if (!loaded.ok()) {
    std::cerr << "error: " << cmd.graph_file.string() << " is not a valid graph:\n" << loaded.error_text();
    return kExitInvalid;
  }
  ExtractRequest request;
  request.nodes = cmd.nodes;
  request.expose = cmd.expose;
  request.asset_file = cmd.asset_file;
  request.graph_file = cmd.graph_out.empty() ? cmd.graph_file : cmd.graph_out;
  request.instance_id = cmd.instance_id;
  request.description = cmd.description;
  request.source = cmd.graph_file.filename().string();
  if (fs::exists(request.asset_file) && !cmd.force) {
    std::cerr << "error: " << request.asset_file.string()
              << " exists: an asset may be used by other graphs; choose another file or pass --force\n";
    return kExitInvalid;
  }
  bool wrote_asset = false;
  // Never leave an asset behind when the graph is not rewritten.
  auto remove_asset = [&] {
    std::error_code ec;
    if (wrote_asset) fs::remove(request.asset_file, ec);
  };
  try {
    const Extraction ex = make_subgraph_asset(*loaded.graph, request);
    write_text_atomically(request.asset_file, ex.asset_text);
    wrote_asset = true;
    const AssetLoad asset = load_subgraph_asset(fs::absolute(request.asset_file).string(), {});
    if (!asset.asset) {
      remove_asset();
      std::cerr << "error: the extracted asset does not load: " << asset.error << "\n";
      return kExitInvalid;
    }
    const Graph rewritten = rewrite_with_instance(*loaded.graph, request, ex, *asset.asset);
    save_graph_file(rewritten, request.graph_file);
    const Node* instance = nullptr;
    for (const auto& n : rewritten.nodes())
      if (const Node* old = loaded.graph->find(n.id); n.type->subgraph == asset.asset && (!old || old->type != n.type))
        instance = &n;
    std::cout << "wrote asset " << request.asset_file.string() << " (" << ex.inputs.size() << " inputs, "
              << ex.outputs.size() << " outputs, " << ex.params.size() << " parameters)\n"
              << "wrote " << request.graph_file.string() << ": " << request.nodes.size()
              << " nodes replaced by instance '" << (instance ? instance->id : "?") << "' (asset \"" << ex.reference
              << "\")\n";
  } catch (const GraphError& e) {
    remove_asset();
    std::cerr << "error: cannot extract a subgraph from " << cmd.graph_file.string() << ": " << e.what() << "\n";
    return kExitInvalid;
  } catch (const std::exception& e) {
    remove_asset();
    std::cerr << "error: cannot write the extraction of " << cmd.graph_file.string() << ": " << e.what() << "\n";
    return kExitEvalFailed;
  }
  return kExitOk;
}

int run_subgraph_make_unique(const MakeUniqueCommand& cmd) {
  LoadResult loaded = load_graph_file(cmd.graph_file);
  if (!loaded.ok()) {
    std::cerr << "error: " << cmd.graph_file.string() << " is not a valid graph:\n" << loaded.error_text();
    return kExitInvalid;
  }
  const fs::path output = cmd.output.empty() ? cmd.graph_file : cmd.output;
  std::error_code ec;
  const fs::path in_dir = fs::weakly_canonical(fs::absolute(cmd.graph_file, ec).parent_path(), ec);
  const fs::path out_dir = fs::weakly_canonical(fs::absolute(output, ec).parent_path(), ec);
  if (in_dir != out_dir) {
    std::cerr << "error: " << output.string() << " is not in the folder of " << cmd.graph_file.string()
              << ": relative paths in the graph (and in the embedded copy) resolve against its folder\n";
    return kExitInvalid;
  }
  if (!cmd.output.empty() && !cmd.force && fs::exists(output) && !fs::equivalent(output, cmd.graph_file, ec)) {
    std::cerr << "error: " << output.string() << " exists; choose another file or pass --force\n";
    return kExitInvalid;
  }
  Graph& graph = *loaded.graph;
  try {
    const std::string shared = [&] {
      const Node* node = graph.find(cmd.node);
      return node && node->type->subgraph ? node->asset : std::string();
    }();
    const MadeUnique made = make_instance_unique(graph, cmd.node);
    save_graph_file(graph, output);
    std::cout << "instance '" << cmd.node << "' now uses the embedded asset \"#" << made.name << "\" (a copy of \""
              << shared << "\", " << made.asset->graph.nodes().size() << " nodes)\n"
              << "wrote " << output.string() << "\n";
  } catch (const GraphError& e) {
    std::cerr << "error: cannot make node '" << cmd.node << "' of " << cmd.graph_file.string()
              << " unique: " << e.what() << "\n";
    return kExitInvalid;
  } catch (const std::exception& e) {
    std::cerr << "error: cannot write " << output.string() << ": " << e.what() << "\n";
    return kExitEvalFailed;
  }
  return kExitOk;
}

}  // namespace orogen::cli
