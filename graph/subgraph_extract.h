#pragma once
// `orogen subgraph extract`: a selection of a graph's nodes becomes a subgraph asset (graph/subgraph.h), and
// the graph is rewritten to use one instance of it in place of the selection, wired identically, so that
// every output stays byte-identical (docs/subgraphs.md, "Extracting a subgraph").
#include <filesystem>
#include <string>
#include <vector>

#include "graph/graph.h"

namespace orogen {

struct SubgraphAsset;

struct ExtractRequest {
  std::vector<std::string> nodes;    // the selection: ids of the graph's nodes
  std::vector<std::string> expose;   // "node.param" of selected nodes, exposed on the instance
  std::filesystem::path asset_file;  // where the asset will be written: relative paths inside are rebased on it
  std::filesystem::path graph_file;  // where the rewritten graph will be written: the instance names the asset
                                     // by a path relative to its folder
  std::string instance_id;           // empty: made from the asset's name
  std::string description;           // of the asset; empty: says where it came from
  std::string source;                // the graph's file name, for that default description
  // Writers (nodes with an output file) are refused unless allowed: every instance of the asset would write the
  // same file. The editor's Group allows them (the user sees the asset and can move the writer out).
  bool allow_writers = false;
};

// What make_subgraph_asset decided, for rewrite_with_instance and to report.
struct Extraction {
  std::string asset_text;  // the asset file
  std::string asset_name;  // its file name without ".orogen-subgraph.json"
  std::string reference;   // how the rewritten graph names it
  struct Input {
    std::string name;
    PortRef source;                // the outside output that fed the selection
    std::vector<PortRef> targets;  // the selected inputs it fed (node, input port)
  };
  struct Output {
    std::string name;
    PortRef source;                                          // the selected output
    std::vector<std::pair<std::string, std::string>> sinks;  // the outside inputs it fed (node, port)
  };
  struct Param {
    std::string name;
    PortRef target;  // node and parameter
  };
  std::vector<Input> inputs;
  std::vector<Output> outputs;
  std::vector<Param> params;
};

// A node moved from a graph in folder `from` to one in folder `to`: its relative input paths (ReadHeightfield's
// `path`, set or default) and its asset path, if it is an instance naming its asset by a relative path, are
// rewritten so that they name the same files. Output files stay as they are (they are the user's choice of
// where to write, relative to wherever the graph is evaluated from).
void rebase_node_paths(Node& node, const std::filesystem::path& from, const std::filesystem::path& to);

// The asset for the selection: inputs are the links entering it (one per outside output, named after the
// first inner input it feeds, made unique), outputs the selected outputs linked from outside (named after the
// port, made unique), parameters the exposed ones (named after the parameter, made unique), each defaulting
// to its current value. Positions start at 0,0 at the selection's top-left corner. Relative input paths and asset paths
// of selected nodes are rebased on the asset's folder. Throws GraphError, naming the nodes, for: an empty selection, an
// unknown or repeated id, an unknown parameter to expose or one of an unselected node, a selection that is not convex
// (an unselected node both fed by and feeding the selection, with the path named: the instance would be in a cycle),
// and selected writers unless request.allow_writers (nodes with an output file: every instance of the asset would write
// the same file; leave them out of the selection and link them to the instance's outputs).
Extraction make_subgraph_asset(const Graph& graph, const ExtractRequest& request);

// `graph` with the selection replaced by an instance of `asset` (loaded from the file make_subgraph_asset's
// text was written to), linked as the selection was; the instance sets no parameter, so the exposed ones take
// their defaults, the selection's values. It takes the place of the first selected node in the node order (a
// local diff) and the selection's top-left corner on the canvas, so that ungrouping puts the nodes back where
// they were. The rest of the graph (domain, folder, positions, interface) is kept.
Graph rewrite_with_instance(const Graph& graph, const ExtractRequest& request, const Extraction& extraction,
                            const SubgraphAsset& asset);

}  // namespace orogen
