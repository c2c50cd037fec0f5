// orogen: evaluate, validate and document terrain graphs from the command line.
#include <iostream>

#include <CLI/CLI.hpp>

#include "cli/commands.h"
#include "cli/plugins.h"
#include "graph/registry.h"

int main(int argc, char** argv) {
  using namespace orogen::cli;
  CLI::App app{"Orogen: node-graph procedural terrain compositor"};
  app.set_version_flag("--version", std::string("orogen ") + OROGEN_VERSION);
  app.require_subcommand(1);
  std::vector<std::string> plugins;
  app.add_option("--plugin", plugins,
                 "Load a node library (.so built with orogen_add_node_library); repeatable, before or after the "
                 "command. The folders of OROGEN_PLUGIN_PATH (separated by ':') are loaded too");
  // Subcommands hand --plugin up to the app, so `orogen nodes --plugin x.so` works as well.
  app.fallthrough();

  EvalCommand eval;
  auto* eval_cmd = app.add_subcommand("eval", "Evaluate a graph file and write its outputs");
  eval_cmd->add_option("FILE", eval.graph_file, "Graph file (.json)")->required();
  eval_cmd->add_option("-o,--output", eval.output_dir, "Output directory; graph output paths resolve inside it")
      ->capture_default_str();
  eval_cmd->add_option("--set", eval.set, "Override a parameter: NODE.PARAM=VALUE (JSON or bare text); repeatable");
  eval_cmd->add_option("--resolution", eval.resolution,
                       "Override the sample counts: WxH (e.g. 2048x2048), or N along x with square cells; cells must "
                       "stay square. Engines' heightmap sizes by name: unreal-505, unreal-1009, unreal-2017, "
                       "unreal-4033, unreal-8129 (Unreal's recommended landscape sizes), unity-513 ... unity-4097 "
                       "(2^n + 1)");
  eval_cmd->add_option(
      "--origin", eval.origin,
      "Move the domain: X,Y in metres, the world position of its first sample (overrides the graph's origin)");
  eval_cmd->add_option("--size", eval.size,
                       "Resize the domain: W,H in metres (overrides the graph's size; the sample counts stay unless "
                       "--resolution is given)");
  eval_cmd->add_option("--tiles", eval.tiles,
                       "Tiled build: cut the domain into NxM tiles (N along x, M along y) that share their border "
                       "samples; each tile is written to its own files, named with the suffix _xI_yJ before the "
                       "extension (--stats too). Each tile is computed with the halo its local nodes need, so the "
                       "tiles join bit for bit and equal the untiled build; nodes that need the whole domain are "
                       "named in a warning (see --global-nodes). Tiles are equal when N divides W - 1 (e.g. 1025 "
                       "samples in 4 tiles of 257)");
  eval_cmd->add_option("--tile", eval.tile,
                       "With --tiles: build only tile I,J (column I along x, row J along y, from 0 at the domain's "
                       "minimum corner, or as --tile-naming names them), e.g. one job of a batch system");
  eval_cmd->add_option("--tile-naming", eval.tile_naming,
                       "With --tiles, which tile is _x0_y0: 'orogen' (default) counts rows from the south (the "
                       "world's y); 'unreal' makes _x0_y0 the top-left (north-west) tile and counts rows down, as "
                       "Unreal Engine's tiled landscape import and World Machine name tiles");
  eval_cmd->add_flag("--merge", eval.merge,
                     "With --tiles, once every tile is built: write each height raster as one file (the untiled "
                     "build's name and bytes) instead of its tiles, streamed a band of rows at a time through one "
                     "process, so none holds the whole raster. 16-bit heights need range 'fixed'; writers that "
                     "cannot merge keep their tiles and say so");
  eval_cmd->add_option("--global-nodes", eval.global_nodes,
                       "With --tiles, how nodes that need the whole domain (reach global: erosion, flow, "
                       "normalization) are built: 'whole' (default) evaluates them once on the whole domain and "
                       "cuts their result into the tiles, so the tiles still join; 'tile' evaluates them on each "
                       "tile alone (memory of a tile only, but seams). Either way a warning names them");
  eval_cmd->add_option("--threads", eval.threads, "Worker threads (0: all cores)")->check(CLI::Range(0, 4096));
  eval_cmd->add_option("--cache-dir", eval.cache_dir, "Persistent cache directory (results survive the process)");
  eval_cmd->add_option("--cache-mb", eval.cache_mb, "In-memory cache bound in MiB (0 to 1e9)")->capture_default_str();
  eval_cmd
      ->add_option("--cache-disk-mb", eval.cache_disk_mb,
                   "Bound of the --cache-dir directory in MiB (0 to 1e9); least recently used entries are evicted")
      ->capture_default_str();
  eval_cmd->add_option("--max-memory", eval.max_memory,
                       "Refuse nodes whose estimated memory exceeds this (MiB, or with a unit: 512M, 8G), per "
                       "process (per rank under MPI); default: the machine's available memory, shared by its ranks");
  eval_cmd->add_option("--stats", eval.stats_file, "Write per-node status, timings and memory as JSON");
  eval_cmd->add_flag("-q,--quiet", eval.quiet, "Print nothing but errors (and the seam warnings of --tiles)");
  eval_cmd->add_flag("--allow-any-path", eval.allow_any_path,
                     "Let the graph write to absolute paths or outside the output directory");

  ValidateCommand validate;
  auto* validate_cmd = app.add_subcommand(
      "validate", "Check a graph file and report every problem: the file, output paths, input files");
  validate_cmd->add_option("FILE", validate.graph_file, "Graph file (.json)")->required();
  validate_cmd->add_option("-o,--output", validate.output_dir, "Output directory the output paths are checked against")
      ->capture_default_str();
  validate_cmd->add_flag("--allow-any-path", validate.allow_any_path,
                         "Accept absolute output paths and paths outside the output directory");

  std::string node_type;
  bool json = false, markdown = false;
  auto* nodes_cmd = app.add_subcommand("nodes", "List node types, or document one");
  nodes_cmd->add_option("TYPE", node_type, "A node type to document in full");
  nodes_cmd->add_flag("--json", json, "Machine-readable output");
  nodes_cmd->add_flag("--markdown", markdown, "The whole reference as Markdown");

  std::vector<std::filesystem::path> migrate_files;
  bool migrate_check = false;
  auto* migrate_cmd = app.add_subcommand(
      "migrate", "Rewrite graph files at the current format version in place (what loading them does in memory)");
  migrate_cmd->add_option("FILES", migrate_files, "Graph files (.json)")->required();
  migrate_cmd->add_flag("--check", migrate_check, "Write nothing; exit 1 if a file is at an older version");

  ExtractCommand extract;
  auto* subgraph_cmd = app.add_subcommand("subgraph", "Work with subgraph assets (docs/subgraphs.md)");
  subgraph_cmd->require_subcommand(1);
  auto* extract_cmd = subgraph_cmd->add_subcommand(
      "extract",
      "Turn a selection of a graph's nodes into a subgraph asset and rewrite the graph to use one instance of it, "
      "wired as the selection was (outputs unchanged)");
  extract_cmd->add_option("FILE", extract.graph_file, "Graph file (.json)")->required();
  extract_cmd->add_option("--nodes", extract.nodes, "The nodes to extract: a,b,c")->required()->delimiter(',');
  extract_cmd->add_option("-o,--output", extract.asset_file, "The asset file to write (NAME.orogen-subgraph.json)")
      ->required();
  extract_cmd
      ->add_option("--expose", extract.expose,
                   "Parameters of selected nodes to expose on the instance: node.param,...; each defaults to its "
                   "current value")
      ->delimiter(',');
  extract_cmd->add_option("--graph-out", extract.graph_out, "Write the rewritten graph here instead of over FILE");
  extract_cmd->add_option("--id", extract.instance_id, "Id of the instance (default: the asset's name)");
  extract_cmd->add_option("--description", extract.description, "Description of the asset");
  extract_cmd->add_flag("--force", extract.force, "Overwrite an existing asset file");

  MakeUniqueCommand make_unique;
  auto* make_unique_cmd = subgraph_cmd->add_subcommand(
      "make-unique",
      "Give an instance its own copy of its asset, embedded in the graph file (\"#name\"), so that editing it "
      "changes no other graph (outputs unchanged)");
  make_unique_cmd->add_option("FILE", make_unique.graph_file, "Graph file (.json)")->required();
  make_unique_cmd->add_option("--node", make_unique.node, "The instance to make unique")->required();
  make_unique_cmd->add_option("-o,--output", make_unique.output,
                              "Write the graph here (in FILE's folder) instead of over FILE");
  make_unique_cmd->add_flag("--force", make_unique.force, "Overwrite an existing output file");

  std::vector<std::string> test_types;
  bool test_all = false;
  auto* test_cmd =
      app.add_subcommand("test-node",
                         "Check node types against the contracts every node passes (declaration, cache key, reach, "
                         "threads) and print a pass/fail table; exit 1 on a failure");
  test_cmd->add_option("TYPE", test_types, "Node types to check (with --plugin, a library's types)");
  test_cmd->add_flag("--all", test_all, "Check every registered type");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitInvalid;
  }

  if (!load_plugins(plugins)) return kExitInvalid;
  try {
    if (*eval_cmd) return run_eval(eval);
    if (*validate_cmd) return run_validate(validate);
    if (*nodes_cmd) return run_nodes(node_type, json, markdown);
    if (*extract_cmd) return run_subgraph_extract(extract);
    if (*make_unique_cmd) return run_subgraph_make_unique(make_unique);
    if (*migrate_cmd) return run_migrate(migrate_files, migrate_check);
    if (*test_cmd) {
      if (test_all)
        for (const orogen::NodeType* t : orogen::NodeRegistry::instance().all()) test_types.push_back(t->name);
      if (test_types.empty()) {
        std::cerr << "error: name a node type to check, or --all\n";
        return kExitInvalid;
      }
      return run_test_node(test_types);
    }
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitEvalFailed;
  }
  return kExitInvalid;
}
