// LEAD'S NOTE TO THE HELPER IN /work/mpi: delete this whole comment block (up to END NOTE) in your first edit of
// this file; it is not code documentation. Rules that bind you:
// ## Common rules for every helper (read carefully)
// 
// You are a senior C++20 engineer on Orogen, a node-graph procedural terrain compositor (repo: /work/main, branch
// `main`). Read `/work/main/docs/architecture.md`, `/work/main/docs/conventions.md` and `../shared/DESIGN.md`
// (relative to /work/main, i.e. /work/shared/DESIGN.md) first, and the issue text with `issues show N` (READ-ONLY:
// never run `issues` subcommands that write, such as `resolved`, `note`, `comment`; only `issues show N` and
// plain `issues`). The project guide (rules that bind you):
// - No toy versions, no stubs called done. Algorithms are the real ones from the literature. Tests check
//   properties that would fail if the algorithm were wrong (conservation, bounds, determinism, analytic values,
//   brute-force references). A test that cannot fail is a defect. Never assert a wall-clock time in a test.
// - Clear errors for every bad input, nothing lost on failure, progress on long work.
// - Dependencies only from Debian packages, added to `scripts/install-deps.sh` (you are root; apt-get works).
//   Nothing downloaded at build time, no code vendored or copied from other projects.
// - Speed is a feature: benchmarks in `bench/` (Google Benchmark); outputs of existing graphs stay byte-identical
//   unless your change means to alter them.
// - One concept per file, names that say what things are, short comments that say why. The code is formatted by
//   `.clang-format` (clang-format-14, 120 columns): run `clang-format-14 -i` on every C++ file you touch;
//   `scripts/test.sh` refuses unformatted files. No line over 120 characters anywhere.
// - Test simulations at small sizes (64²–256²), keep your new tests fast (the whole CI, Release + ASan/UBSan
//   builds and suites, must stay under 30 min warm on 2 cores).
// - Look at what you make: render new terrains/maps to PNG and view them with your file viewer tool.
// 
// Machine: 2 cores, shared with 3 other helpers and the lead. Therefore:
// - Work ONLY in your own git worktree (given in your prompt); never touch /work/main or other worktrees.
// - Configure your own build dir inside your worktree: `cd W && export CCACHE_BASEDIR=$PWD CCACHE_NOHASHDIR=1 &&
//   cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release && cmake --build build/release -j2 -- -k 0`
//   (ccache is warm for the current main, so the first build is mostly cache hits). Build only the targets you
//   need where you can (`cmake --build build/release --target X`).
// - Do NOT run the full ctest suite repeatedly; run the tests you touch (`ctest --test-dir build/release -R
//   'Pattern' -j2`), and the full Release suite once at the end. Do not build the sanitizer configuration unless
//   your work is risky in memory terms; if you do, use `build/sanitize` in your worktree with
//   `-DCMAKE_BUILD_TYPE=RelWithDebInfo -DOROGEN_SANITIZE=ON -DOROGEN_EDITOR=OFF -DOROGEN_BENCH=OFF` and build
//   only your test targets.
// - Commit in small, honest steps with clear messages on your branch (git user is configured). Commit early: any
//   uncommitted work is lost if you run out of time. Keep your branch mergeable into main (the lead merges).
// - Time limit: you must stop by the deadline given in your prompt, with everything committed and a final report.
// - Your final message (the report) must say: what you built (files), what is tested and how, measured figures
//   with the commands that reproduce them, what remains undone from the issue (honestly, item by item), and
//   anything you noticed and left alone. Keep it under 80 lines.
// 
// END NOTE

#pragma once
// Tiled builds (`orogen eval --tiles NxM [--tile I,J]`): the graph's domain cut into N x M tiles that share
// their border samples with their neighbours (tile (I, J) of a W-sample axis cut in N covers samples
// floor(I (W-1) / N) ... floor((I+1) (W-1) / N), both ends included), every tile written to its own files
// with the suffix `_xI_yJ`.
//
// Each node is evaluated on the tile expanded by the halo its consumers need, from the reach every node
// type declares (graph/node_type.h), clipped to the graph's domain: a writer sees exactly its tile, the
// node feeding it the tile plus that node's consumers' halos, and so on upstream. Point-wise and local
// nodes then reproduce, inside the tile, the full-domain result bit for bit, so neighbouring tiles agree on
// their shared borders and the tiles put together are the untiled build.
//
// Nodes whose result depends on the whole domain (reach global or undeclared; writers and
// domain-independent nodes excepted) are either evaluated on the whole domain and cut into the tiles
// (GlobalNodes::Whole: the tiles still join, and every tile's request has the same key for them, so the
// cache computes them once), or on their tile's part alone (GlobalNodes::PerTile: each tile needs only its
// own memory, but they do not join). Only rasters can be cut: a whole-domain node with no Heightfield or
// Image output (a mesh, curves, points) is evaluated per tile in both modes. seam_warnings() names them.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/domain.h"
#include "graph/graph.h"

namespace orogen::cli {

// "NxM": tile counts along x and y, each in [1, 4096]. nullopt and `error` set if malformed.
std::optional<glm::ivec2> parse_tile_counts(const std::string& text, std::string& error);
// "I,J": a tile's column and row (from 0), checked against `counts`. nullopt and `error` set if malformed
// or out of range.
std::optional<glm::ivec2> parse_tile_index(const std::string& text, glm::ivec2 counts, std::string& error);
// "X,Y": two finite numbers (for --origin and --size); `option` names the option in the error. With
// `positive`, both must be > 0.
std::optional<glm::dvec2> parse_number_pair(const std::string& text, const std::string& option, bool positive,
                                            std::string& error);

// Empty if a domain of `resolution` samples can be cut into `counts` tiles of at least 2 samples per axis
// (shared borders included), else why not.
std::string check_tile_counts(glm::ivec2 resolution, glm::ivec2 counts);

struct TileWindow {
  glm::ivec2 index{0, 0};  // (I, J)
  glm::ivec2 first{0, 0};  // first sample of the tile in the full domain
  glm::ivec2 size{1, 1};   // sample counts, shared borders included
};
// Tile `index` of a domain of `resolution` samples cut into `counts` tiles.
TileWindow tile_window(glm::ivec2 resolution, glm::ivec2 counts, glm::ivec2 index);

// "_x1_y0": the suffix of tile (1, 0)'s files.
std::string tile_suffix(glm::ivec2 index);
// `path` with `suffix` before its extension: "maps/height.exr" -> "maps/height_x1_y0.exr".
std::string with_suffix(const std::string& path, const std::string& suffix);
// Adds `suffix` to every output-file parameter of the graph's writers.
void add_output_suffix(Graph& graph, const std::string& suffix);

enum class GlobalNodes { Whole, PerTile };
// "whole" or "tile" (the --global-nodes option); nullopt otherwise.
std::optional<GlobalNodes> parse_global_nodes(const std::string& text);

// The nodes of `graph` that need the whole domain: a global or undeclared reach, not a writer, not
// domain-independent.
std::vector<std::string> whole_domain_nodes(const Graph& graph);

// The domain each node is evaluated on for tile `window` of `full` (EvalRequest::node_domains): the tile
// expanded by the halos downstream of the node plus the node's own halo, clipped to `full`; with
// GlobalNodes::Whole, `full` for the whole-domain nodes and everything upstream of them.
std::map<std::string, Domain> tile_node_domains(const Graph& graph, const Domain& full, const TileWindow& window,
                                                GlobalNodes global = GlobalNodes::Whole);

// What a tiled build of `graph` cannot make seamless or cheap, one message per node, naming it: the
// whole-domain nodes (PerTile: with the writers whose outputs then do not join; Whole: computed on the
// whole domain), and 16-bit heightfield writers whose height mapping follows each tile's own range.
std::vector<std::string> seam_warnings(const Graph& graph, GlobalNodes global);

}  // namespace orogen::cli
