#pragma once
// The `orogen` subcommands. Each returns the process exit code:
// 0 success, 1 evaluation failed (or was interrupted), 2 invalid graph or usage.
#include <filesystem>
#include <string>
#include <vector>

namespace orogen::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitEvalFailed = 1;
inline constexpr int kExitInvalid = 2;

struct EvalCommand {
  std::filesystem::path graph_file;
  std::filesystem::path output_dir = "out";
  std::vector<std::string> set;
  std::string resolution;  // "WxH", empty: the graph's
  int threads = 0;
  std::filesystem::path cache_dir;
  std::string cache_mb = "2048";       // in-memory cache bound, MiB
  std::string cache_disk_mb = "4096";  // bound of --cache-dir, MiB
  std::string max_memory;              // empty: the machine's available memory
  std::filesystem::path stats_file;
  bool quiet = false;
  bool allow_any_path = false;
  std::string origin;                  // "X,Y": the domain's origin, metres; empty: the graph's
  std::string size;                    // "W,H": the domain's size, metres; empty: the graph's
  std::string tiles;                   // "NxM": a tiled build (cli/tiling.h); empty: one build of the whole domain
  std::string tile;                    // "I,J": only this tile of --tiles; empty: every tile
  std::string global_nodes;            // "whole" or "tile": how --tiles evaluates whole-domain nodes; empty: whole
  bool merge = false;                  // with --tiles: each height raster's tiles become one file (cli/merge_tiles.h)
  std::string tile_naming = "orogen";  // "orogen" (_y0 south) or "unreal" (_x0_y0 top-left): cli/tile_naming.h
};

int run_eval(const EvalCommand& cmd);
struct ValidateCommand {
  std::filesystem::path graph_file;
  std::filesystem::path output_dir = "out";  // as for eval: output paths are checked against it
  bool allow_any_path = false;
};

int run_validate(const ValidateCommand& cmd);
int run_nodes(const std::string& type, bool json, bool markdown);
// Rewrites each file at the current format version (exit 2 if one cannot be read or migrated); check_only:
// only say which files are older (exit 1 if any is).
int run_migrate(const std::vector<std::filesystem::path>& files, bool check_only);
struct ExtractCommand {
  std::filesystem::path graph_file;
  std::vector<std::string> nodes;   // the selection
  std::vector<std::string> expose;  // NODE.PARAM of selected nodes
  std::filesystem::path asset_file;
  std::filesystem::path graph_out;  // empty: rewrite graph_file in place
  std::string instance_id;
  std::string description;
  bool force = false;  // overwrite an existing asset file
};
// `orogen subgraph extract`: writes the asset and the rewritten graph (exit 2 if the selection cannot be
// extracted, with the reason).
int run_subgraph_extract(const ExtractCommand& cmd);
struct MakeUniqueCommand {
  std::filesystem::path graph_file;
  std::string node;              // the instance
  std::filesystem::path output;  // empty: rewrite graph_file in place
  bool force = false;            // overwrite an existing output file
};
// `orogen subgraph make-unique`: the instance uses an embedded copy of its asset (exit 2, nothing written, if it
// cannot, with the reason).
int run_subgraph_make_unique(const MakeUniqueCommand& cmd);
// Runs the node contracts on each type and prints a table; 1 if any contract fails.
int run_test_node(const std::vector<std::string>& types);

}  // namespace orogen::cli
