#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <iostream>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/graph_overrides.h"
#include "cli/merge_tiles.h"
#include "cli/mosaic.h"
#include "cli/mpi_rank_group.h"
#include "cli/progress_display.h"
#include "cli/stats_report.h"
#include "cli/tile_graph_stages.h"
#include "cli/tile_memory.h"
#include "cli/tile_result_spill.h"
#include "cli/tile_assignment.h"
#include "cli/tile_naming.h"
#include "cli/tiling.h"
#include "evaluator/evaluator.h"
#include "evaluator/memory_estimate.h"
#include "graph/atomic_file.h"
#include "graph/graph_file.h"
#include "graph/output_path.h"
#include "nodes/io/heightfield_file.h"

namespace orogen::cli {
namespace {

// Why a node that runs across the tiles does not fit: this rank holds `tiles` of them at once, each needing `need`
// bytes (estimate_node_bytes on tile domain `d`), and how many ranks (or smaller tiles) would do.
std::string across_memory_refusal(const Node& node, const Domain& d, std::uint64_t need, std::size_t tiles,
                                  std::uint64_t limit, std::size_t all_tiles) {
  const std::uint64_t fit = limit / need;  // tiles a rank can hold, at least 1 (the caller checked one)
  const std::size_t ranks = static_cast<std::size_t>((all_tiles + fit - 1) / fit);
  return "node '" + node.id +
         "' runs across the tiles, and a rank holds its state for all of its tiles at once: " + std::to_string(tiles) +
         " tiles of " + std::to_string(d.resolution.x) + "x" + std::to_string(d.resolution.y) +
         " samples need at least " + format_bytes(need * tiles) + " (" + node.type->name + ": " + format_bytes(need) +
         " a tile); the memory limit is " + format_bytes(limit) + " a rank (--max-memory); run it on " +
         std::to_string(ranks) + " ranks or more, or raise --max-memory";
}

CancelToken g_interrupt;  // set by SIGINT/SIGTERM; CancelToken is a lock-free atomic, safe in a handler

extern "C" void on_interrupt(int) { g_interrupt.cancel(); }

}  // namespace

namespace {

// One build of the command: the whole domain, or one tile of a tiled build.
struct Build {
  std::optional<TileWindow> tile;  // empty: the whole domain, files as the graph names them
  std::string suffix;              // file-name suffix of the tile ("_x1_y0"), empty for the whole domain
};

// The stats document of one build, with the tile it covers.
std::string stats_with_tile(const EvalResult& result, const Graph& graph, const Build& build, glm::ivec2 counts,
                            const Domain& full, const RankGroup& group) {
  std::string text = stats_json(result, &graph);
  if (!build.tile) return text;
  auto doc = nlohmann::json::parse(text);
  const Domain d = full.subdomain(build.tile->first.x, build.tile->first.y, build.tile->size.x, build.tile->size.y);
  doc["tile"] = {{"index", {build.tile->index.x, build.tile->index.y}},
                 {"tiles", {counts.x, counts.y}},
                 {"suffix", build.suffix},
                 {"first_sample", {build.tile->first.x, build.tile->first.y}},
                 {"resolution", {d.resolution.x, d.resolution.y}},
                 {"min_corner", {d.min_corner().x, d.min_corner().y}},
                 {"size", {d.size().x, d.size().y}}};
  if (group.size() > 1) doc["tile"]["rank"] = {{"rank", group.rank()}, {"ranks", group.size()}};
  return doc.dump(2) + "\n";
}

// Node counts of the builds of one rank, summed over the ranks for the job's summary.
struct BuildCounts {
  std::size_t computed = 0, cached = 0, failed = 0, skipped = 0, tiles = 0, failed_tiles = 0;
  double milliseconds = 0.0;
};

BuildCounts job_counts(RankGroup& group, const BuildCounts& mine) {
  std::ostringstream out;
  out << mine.computed << ' ' << mine.cached << ' ' << mine.failed << ' ' << mine.skipped << ' ' << mine.tiles << ' '
      << mine.failed_tiles << ' ' << mine.milliseconds;
  BuildCounts sum;
  for (const auto& text : group.all_gather(out.str())) {
    std::istringstream in(text);
    BuildCounts c;
    in >> c.computed >> c.cached >> c.failed >> c.skipped >> c.tiles >> c.failed_tiles >> c.milliseconds;
    sum.computed += c.computed, sum.cached += c.cached, sum.failed += c.failed, sum.skipped += c.skipped;
    sum.tiles += c.tiles, sum.failed_tiles += c.failed_tiles;
    sum.milliseconds = std::max(sum.milliseconds, c.milliseconds);  // the ranks run side by side
  }
  return sum;
}

// Refuses what a distributed build (several ranks) cannot do; empty if `ranks` is 1.
std::vector<std::string> distribution_errors(int ranks, bool tiled, bool one_tile, glm::ivec2 counts) {
  if (ranks == 1) return {};
  const std::string on = "launched on " + std::to_string(ranks) + " ranks: ";
  if (!tiled)
    return {on + "a distributed build spreads tiles over the ranks; add --tiles NxM with at least " +
            std::to_string(ranks) + " tiles (e.g. --tiles " + std::to_string(ranks) + "x1)"};
  if (one_tile) return {on + "--tile builds one tile in one process; drop --tile, or run without mpirun"};
  const long long tiles = static_cast<long long>(counts.x) * counts.y;
  if (tiles < ranks)
    return {on + "--tiles " + std::to_string(counts.x) + "x" + std::to_string(counts.y) + " has only " +
            std::to_string(tiles) + " tiles, so " + std::to_string(ranks - tiles) +
            " ranks would have none; use at most " + std::to_string(tiles) + " ranks, or more tiles"};
  return {};
}

int run_eval_on(const EvalCommand& cmd, RankGroup& group);

// After every tile of a tiled build succeeded: with --merge the merged files (cli/merge_tiles.h), then the GDAL
// mosaics of the rasters not merged (cli/mosaic.h). Returns false (error printed) if one cannot be written.
bool write_tiled_outputs(const Graph& graph, const Domain& domain, glm::ivec2 counts, TileNaming naming,
                         const OutputPolicy& policy, bool quiet, bool merge) {
  std::vector<std::string> warnings;
  std::set<std::string> merged;
  if (merge) try {
      MergeResult m = merge_tiles(graph, domain, counts, naming, policy, [quiet](const std::string& file) {
        if (!quiet) std::cerr << "merging the tiles into " << file << "\n";
      });
      for (const auto& w : m.warnings) std::cerr << "warning: --merge: " << w << "\n";
      if (!quiet && !m.files.empty())
        std::cerr << m.files.size() << (m.files.size() == 1 ? " merged file" : " merged files")
                  << " of the tiles, e.g. " << m.files.front() << "\n";
      merged = std::move(m.merged_nodes);
    } catch (const std::exception& e) {
      std::cerr << "error: cannot merge the tiles: " << e.what() << "\n";
      return false;
    }
  try {
    const auto written = write_mosaics(graph, domain, counts, naming, policy, warnings, merged);
    for (const auto& w : warnings) std::cerr << "warning: --tiles: " << w << "\n";
    if (!quiet && !written.empty())
      std::cerr << written.size() << (written.size() == 1 ? " mosaic" : " mosaics") << " of the tiles (GDAL VRT), e.g. "
                << written.front() << "\n";
    return true;
  } catch (const std::exception& e) {
    std::cerr << "error: cannot write the mosaics of the tiles: " << e.what() << "\n";
    return false;
  }
}

}  // namespace

int run_eval(const EvalCommand& cmd) {
  std::string why;
  const auto group = start_rank_group(why);
  if (!group) {
    std::cerr << "error: " << why << "\n";
    return kExitInvalid;
  }
  if (group->size() == 1) return run_eval_on(cmd, *group);
  // On several ranks an exception must stop the whole job: the other ranks would wait for this one forever.
  try {
    return run_eval_on(cmd, *group);
  } catch (const std::exception& e) {
    std::cerr << "error: rank " << group->rank() << ": " << e.what() << "\n";
  } catch (...) {
    std::cerr << "error: rank " << group->rank() << ": unknown exception\n";
  }
  group->abort(kExitEvalFailed);
  return kExitEvalFailed;  // not reached
}

namespace {

int run_eval_on(const EvalCommand& cmd, RankGroup& group) {
  const bool root = group.rank() == 0, distributed = group.size() > 1;
  auto loaded = load_graph_file(cmd.graph_file);
  if (!loaded.ok()) {
    if (root) std::cerr << cmd.graph_file.string() << ": invalid graph\n" << loaded.error_text();
    return kExitInvalid;
  }
  if (root && !cmd.quiet)
    for (const auto& w : loaded.warnings) std::cerr << "warning: " << w.str() << "\n";
  Graph graph = std::move(*loaded.graph);

  std::vector<std::string> errors;
  // Subgraph instances become plain nodes here, so tiling, reach and the reports see ordinary nodes.
  // Its errors are reported with the other option errors below.
  expand_for_evaluation(graph, cmd.set, errors);
  std::string why;
  if (!cmd.origin.empty()) {
    if (auto o = parse_number_pair(cmd.origin, "--origin", false, why))
      graph.domain.origin = *o;
    else
      errors.push_back(why);
  }
  if (!cmd.size.empty()) {  // before --resolution, whose single-number form follows the size
    if (auto sz = parse_number_pair(cmd.size, "--size", true, why))
      graph.domain.size = *sz;
    else
      errors.push_back(why);
  }
  if (!cmd.resolution.empty()) {
    if (auto r = resolution_for(cmd.resolution, graph.domain.size, why))
      graph.domain.resolution = *r;
    else
      errors.push_back(why);
  }
  glm::ivec2 counts{1, 1};
  std::optional<glm::ivec2> only_tile;
  bool tiled = false;
  const auto naming = parse_tile_naming(cmd.tile_naming);
  if (!naming) errors.push_back("--tile-naming '" + cmd.tile_naming + "': expected 'orogen' or 'unreal'");
  const TileNaming tile_naming = naming.value_or(TileNaming::Orogen);
  if (cmd.tiles.empty() && naming && *naming != TileNaming::Orogen)
    errors.push_back("--tile-naming " + cmd.tile_naming + " needs --tiles NxM: it names the files of a tiled build");
  if (!cmd.tiles.empty()) {
    if (auto c = parse_tile_counts(cmd.tiles, why)) {
      counts = *c;
      tiled = true;
      if (!cmd.tile.empty()) {
        if (auto t = parse_tile_index(cmd.tile, counts, why))
          only_tile = named_tile_index(tile_naming, *t, counts);  // --tile names a tile as its files do
        else
          errors.push_back(why);
      }
    } else {
      errors.push_back(why);
    }
  } else if (!cmd.tile.empty()) {
    errors.push_back("--tile " + cmd.tile + " needs --tiles NxM: it picks one tile of a tiled build");
  }
  GlobalNodes global = GlobalNodes::Whole;
  if (!cmd.global_nodes.empty()) {
    if (cmd.tiles.empty())
      errors.push_back("--global-nodes " + cmd.global_nodes +
                       " needs --tiles NxM: it says how a tiled build "
                       "evaluates nodes that need the whole domain");
    else if (auto g = parse_global_nodes(cmd.global_nodes))
      global = *g;
    else
      errors.push_back("--global-nodes '" + cmd.global_nodes + "': expected 'whole' or 'tile'");
  }
  const Domain domain = graph.domain.to_domain();
  if (tiled)
    if (auto e = check_tile_counts(domain.resolution, counts); !e.empty()) errors.push_back(e);
  if (cmd.merge) {
    if (!tiled || only_tile)
      errors.push_back("--merge joins the files of every tile: it needs --tiles NxM without --tile");
    for (auto& e : merge_errors(graph)) errors.push_back(std::move(e));
  }
  OutputPolicy policy{cmd.output_dir, cmd.allow_any_path};
  {
    // Tiles write suffixed names; two writers collide in one tile exactly when they collide in every tile.
    Graph named = graph;
    if (tiled) add_output_suffix(named, tile_suffix({0, 0}));
    // Output paths, and input files before anything is computed (as validate checks them).
    const FileCheck files = check_files(named, policy);
    for (auto& e : files.errors) errors.push_back(std::move(e));
    if (!cmd.quiet)
      for (const auto& w : files.warnings) std::cerr << "warning: " << w << "\n";
  }
  const auto cache_mb = parse_number(cmd.cache_mb, 0.0, 1e9);
  if (!cache_mb) errors.push_back("--cache-mb '" + cmd.cache_mb + "': expected a number of MiB from 0 to 1e9");
  const auto cache_disk_mb = parse_number(cmd.cache_disk_mb, 0.0, 1e9);
  if (!cache_disk_mb)
    errors.push_back("--cache-disk-mb '" + cmd.cache_disk_mb + "': expected a number of MiB from 0 to 1e9");
  // By default a rank may take its share of what this machine has free.
  std::uint64_t max_memory = available_memory_bytes() / static_cast<std::uint64_t>(std::max(1, group.local_size()));
  if (!cmd.max_memory.empty()) {
    if (auto m = parse_memory_size(cmd.max_memory); m && *m > 0)
      max_memory = *m;
    else
      errors.push_back("--max-memory '" + cmd.max_memory + "': expected a positive size such as 4096, 512M or 8G");
  }
  if (auto e = check_domain(domain); !e.empty()) errors.push_back(e);
  for (auto& e : distribution_errors(group.size(), tiled, only_tile.has_value(), counts)) errors.push_back(e);

  // The builds: the whole domain, or the tiles asked for; on several ranks, this rank's tiles
  // (cli/tile_assignment.h).
  std::vector<Build> builds;
  if (errors.empty()) {
    if (!tiled) {
      builds.push_back({});
    } else if (distributed) {
      for (const glm::ivec2 t : tiles_of_rank(counts, group.rank(), group.size()))
        builds.push_back(
            {tile_window(domain.resolution, counts, t), tile_suffix(named_tile_index(tile_naming, t, counts))});
    } else {
      for (int j = 0; j < counts.y; ++j)
        for (int i = 0; i < counts.x; ++i)
          if (!only_tile || *only_tile == glm::ivec2(i, j))
            builds.push_back({tile_window(domain.resolution, counts, {i, j}),
                              tile_suffix(named_tile_index(tile_naming, {i, j}, counts))});
    }
  }
  // Tile-graph nodes run across the tiles when every tile is built (cli/tile_graph_stages.h).
  std::set<std::string> across;
  if (errors.empty() && tiled && !only_tile) across = across_tile_nodes(graph, domain, global);
  if (errors.empty() && max_memory > 0) {
    // Every tile of a build needs about the same: check the middle one (the widest halos), or the one asked for.
    std::map<std::string, Domain> node_domains;
    if (tiled)
      node_domains = tile_node_domains(
          graph, domain, tile_window(domain.resolution, counts, only_tile.value_or(counts / 2)), global, across);
    for (const auto& node : graph.nodes()) {
      const auto it = node_domains.find(node.id);
      const Domain& d = it != node_domains.end() ? it->second : domain;
      const std::vector<ParamValue> params = graph.effective_params(node);
      CostQuery query{*node.type, d, ParamView(*node.type, params), nullptr, graph.directory, {}};
      for (const auto& port : node.type->inputs) query.linked.push_back(node.inputs.contains(port.name));
      const auto need = estimate_node_bytes(query);
      if (need > max_memory) {
        errors.push_back("node '" + node.id + "': " + memory_refusal(*node.type, d, need, max_memory));
      } else if (across.count(node.id) && need * builds.size() > max_memory) {
        // Across the tiles a rank holds the node's state for all its tiles at once (cli/tile_graph_stages.h).
        errors.push_back(across_memory_refusal(node, d, need, builds.size(), max_memory,
                                               static_cast<std::size_t>(counts.x) * counts.y));
      }
    }
  }
  if (distributed) {
    // Ranks on different machines may judge differently (--max-memory defaults to each machine's available
    // memory): agree, so that no rank builds while another has given up. Rank 0 reports the first rank's errors.
    std::string mine;
    for (const auto& e : errors)
      mine += "error: " + (root ? "" : "rank " + std::to_string(group.rank()) + ": ") + e + "\n";
    const auto all = group.all_gather(mine);
    const auto first = std::find_if(all.begin(), all.end(), [](const std::string& s) { return !s.empty(); });
    if (first != all.end()) {
      if (root) std::cerr << *first;
      return kExitInvalid;
    }
  }
  if (!errors.empty()) {
    for (const auto& e : errors) std::cerr << "error: " << e << "\n";
    return kExitInvalid;
  }
  // Nodes that need the whole domain cost the whole domain's memory or leave seams: say which (even with
  // --quiet).
  if (tiled && root)
    for (const auto& w : seam_warnings(graph, global, across)) std::cerr << "warning: --tiles: " << w << "\n";
  if (distributed && root && !cmd.quiet)
    std::cerr << counts.x * counts.y << " tiles over " << group.size() << " ranks (" << builds.size()
              << " on rank 0; cli/tile_assignment.h), rank 0 reporting its own\n";
  // Only rank 0 speaks, errors aside.
  const bool quiet = cmd.quiet || !root;

  EvaluatorOptions options;
  options.threads = cmd.threads;
  // Ranks on one machine share its cores: by default each takes its share.
  if (options.threads == 0 && group.local_size() > 1)
    options.threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()) / group.local_size());
  options.cache_bytes = static_cast<std::size_t>(*cache_mb * 1024.0 * 1024.0);
  options.cache_dir = cmd.cache_dir;
  options.cache_disk_bytes = static_cast<std::uint64_t>(*cache_disk_mb * 1024.0 * 1024.0);
  options.max_memory = max_memory;
  // Temporaries a killed run left in the output directory (the cache sweeps its own directory).
  remove_stale_temporaries(cmd.output_dir, 16);
  options.output = policy;
  Evaluator evaluator(options);

  const bool live = !quiet && ::isatty(STDERR_FILENO);
  BuildCounts counted;
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  // The across-tile nodes' results of this rank's tiles, on disk in the output folder until their tile is built.
  std::unique_ptr<TileResultSpill> across_results;
  if (!across.empty()) {
    TileGraphStages stages;
    stages.graph = &graph;
    stages.domain = domain;
    stages.counts = counts;
    stages.global = global;
    stages.across = across;
    for (const Build& build : builds) stages.tiles.push_back(build.tile->index);
    stages.output = policy;
    stages.cancel = &g_interrupt;
    stages.quiet = quiet;
    try {
      across_results = std::make_unique<TileResultSpill>(cmd.output_dir);
      run_tile_graph_stages(stages, evaluator, group, *across_results);
    } catch (const TileGraphStageError& e) {
      std::signal(SIGINT, SIG_DFL);
      std::signal(SIGTERM, SIG_DFL);
      std::cerr << (e.cancelled ? "" : "error: ") << e.what() << (e.cancelled ? ": nothing partial was written" : "")
                << "\n";
      if (distributed) {
        // Ranks that stopped together meet once more, so none is taken down by the launcher before it has said so.
        if (e.every_rank) group.barrier();
        if (e.cancelled) std::_Exit(kExitEvalFailed);
        std::cerr << "error: stopping every rank\n";
        group.abort(kExitEvalFailed);
      }
      return kExitEvalFailed;
    } catch (const std::runtime_error& e) {  // the spill could not be written or read (a full disk)
      std::signal(SIGINT, SIG_DFL);
      std::signal(SIGTERM, SIG_DFL);
      std::cerr << "error: " << (distributed ? "rank " + std::to_string(group.rank()) + ": " : std::string())
                << "keeping the across-tile results: " << e.what() << "\n";
      if (distributed) group.abort(kExitEvalFailed);
      return kExitEvalFailed;
    }
  }
  // A build's graph (a tile's writers write files with its suffix) and its nodes' domains.
  const auto tile_graph_of = [&](const Build& build) {
    Graph g = graph;
    if (build.tile) add_output_suffix(g, build.suffix);
    return g;
  };
  const auto node_domains_of = [&](const Graph& g, const Build& build) {
    return build.tile ? tile_node_domains(g, domain, *build.tile, global, across) : std::map<std::string, Domain>{};
  };
  // Tiles are evaluated one after another; the memory cache keeps only the results a later tile looks up
  // (cli/tile_memory.h), so the build holds one tile's working set, not every tile's results.
  std::vector<KeySet> wanted_later;
  if (tiled) {
    std::vector<std::map<std::string, CacheKey>> keys;
    std::vector<std::set<std::string>> given;
    for (std::size_t b = 0; b < builds.size(); ++b) {
      const Graph g = tile_graph_of(builds[b]);
      keys.push_back(compute_cache_keys(g, domain, policy, node_domains_of(g, builds[b])));
      given.push_back(across_results ? across_results->nodes(b) : std::set<std::string>{});
    }
    wanted_later = keys_wanted_later(graph, keys, given);
  }
  for (std::size_t b = 0; b < builds.size(); ++b) {
    const Build& build = builds[b];
    Graph tile_graph = tile_graph_of(build);
    EvalRequest request;
    request.domain = domain;
    request.cancel = &g_interrupt;
    std::string label;
    if (build.tile) {
      request.node_domains = node_domains_of(tile_graph, build);
      if (across_results) {
        try {
          request.given_results = across_results->take(b);
        } catch (const std::runtime_error& e) {
          std::cerr << "error: " << (distributed ? "rank " + std::to_string(group.rank()) + ": " : std::string())
                    << "reading the across-tile results back: " << e.what() << "\n";
          if (distributed) group.abort(kExitEvalFailed);
          std::signal(SIGINT, SIG_DFL);
          std::signal(SIGTERM, SIG_DFL);
          return kExitEvalFailed;
        }
      }
      request.keep_in_memory = [&kept = wanted_later[b]](const CacheKey& key) { return kept.count(key) > 0; };
      const Domain d =
          domain.subdomain(build.tile->first.x, build.tile->first.y, build.tile->size.x, build.tile->size.y);
      const glm::ivec2 named = named_tile_index(tile_naming, build.tile->index, counts);
      label = (distributed ? "rank " + std::to_string(group.rank()) + ": " : std::string()) + "tile " +
              std::to_string(named.x) + "," + std::to_string(named.y) + " (" + std::to_string(b + 1) + "/" +
              std::to_string(builds.size()) + ")";
      if (!quiet) std::cerr << label << ": " << d.describe() << ", files *" << build.suffix << ".*\n";
    }
    ProgressDisplay display(stderr, tile_graph.nodes().size());
    if (live) request.on_event = [&](const EvalEvent& e) { display.on_event(e); };
    const EvalResult result = evaluator.evaluate(tile_graph, request);
    // This tile's share of the across-tile results is done with (kept in memory only if a later tile wants it).
    request.given_results.clear();
    if (live) display.finish();
    counted.milliseconds += result.milliseconds;

    if (!cmd.stats_file.empty()) {
      const auto stats_path =
          build.tile ? std::filesystem::path(with_suffix(cmd.stats_file.string(), build.suffix)) : cmd.stats_file;
      try {
        write_text_atomically(stats_path, stats_with_tile(result, tile_graph, build, counts, domain, group));
      } catch (const std::exception& e) {
        std::cerr << "error: cannot write stats to " << stats_path.string() << ": " << e.what() << "\n";
        if (distributed) group.abort(kExitEvalFailed);
        std::signal(SIGINT, SIG_DFL);
        std::signal(SIGTERM, SIG_DFL);
        return kExitEvalFailed;
      }
    }

    std::size_t computed = 0, cached = 0, failed = 0, skipped = 0;
    for (const auto& [id, r] : result.nodes) {
      switch (r.status) {
        case NodeStatus::Computed:
          ++computed;
          break;
        case NodeStatus::Cached:
          ++cached;
          break;
        case NodeStatus::Failed:
          ++failed;
          std::cerr << "error: " << (label.empty() ? "" : label + ": ") << "node '" << id << "' failed: " << r.message
                    << "\n";
          break;
        case NodeStatus::Skipped:
          ++skipped;
          break;
        default:
          break;
      }
    }
    counted.computed += computed, counted.cached += cached, counted.failed += failed, counted.skipped += skipped;
    ++counted.tiles;
    if (failed > 0) ++counted.failed_tiles;
    if (result.cancelled) {
      std::signal(SIGINT, SIG_DFL);
      std::signal(SIGTERM, SIG_DFL);
      std::cerr << "interrupted" << (label.empty() ? "" : " in " + label)
                << ": nothing partial was written or cached\n";
      // The launcher stops the other ranks when one exits with an error (a second MPI_Abort would only add noise).
      if (distributed) std::_Exit(kExitEvalFailed);
      return kExitEvalFailed;
    }
    // A failed tile fails the job: on several ranks, at once (its node's error is printed above, with the rank
    // and the tile), so that no rank builds on for nothing.
    if (failed > 0 && distributed) {
      std::cerr << "error: " << label << ": stopping every rank\n";
      group.abort(kExitEvalFailed);
    }
    if (!quiet) {
      std::fprintf(stderr, "%s%zu computed, %zu cached, %zu failed, %zu skipped in %.1f ms\n",
                   label.empty() ? "" : (label + ": ").c_str(), computed, cached, failed, skipped, result.milliseconds);
    }
  }
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (distributed) {
    const BuildCounts job = job_counts(group, counted);
    if (root && !cmd.quiet)
      std::fprintf(stderr,
                   "%zu tiles built on %d ranks, %zu with failures: %zu computed, %zu cached, %zu failed, "
                   "%zu skipped in %.1f ms (the slowest rank)\n",
                   job.tiles, group.size(), job.failed_tiles, job.computed, job.cached, job.failed, job.skipped,
                   job.milliseconds);
    if (job.failed != 0) return kExitEvalFailed;
    return !root || write_tiled_outputs(graph, domain, counts, tile_naming, policy, cmd.quiet, cmd.merge)
               ? kExitOk
               : kExitEvalFailed;
  }
  if (tiled && !cmd.quiet && builds.size() > 1)
    std::fprintf(stderr, "%zu tiles built, %zu with failures, in %.1f ms\n", builds.size(), counted.failed_tiles,
                 counted.milliseconds);
  if (counted.failed != 0) return kExitEvalFailed;
  if (tiled && !only_tile && !write_tiled_outputs(graph, domain, counts, tile_naming, policy, cmd.quiet, cmd.merge))
    return kExitEvalFailed;
  return kExitOk;
}

}  // namespace

int run_validate(const ValidateCommand& cmd) {
  auto loaded = load_graph_file(cmd.graph_file);
  if (!loaded.ok()) {
    std::cerr << cmd.graph_file.string() << ": invalid graph\n" << loaded.error_text();
    return kExitInvalid;
  }
  const std::size_t node_count = loaded.graph->nodes().size();
  Graph graph = std::move(*loaded.graph);
  std::vector<std::string> expansion_errors;
  if (!expand_for_evaluation(graph, {}, expansion_errors)) {
    std::cerr << cmd.graph_file.string() << ": invalid graph\n";
    for (const auto& e : expansion_errors) std::cerr << "error: " << e << "\n";
    return kExitInvalid;
  }
  const FileCheck files = check_files(graph, OutputPolicy{cmd.output_dir, cmd.allow_any_path});
  for (const auto& w : loaded.warnings) std::cerr << "warning: " << w.str() << "\n";
  for (const auto& w : files.warnings) std::cerr << "warning: " << w << "\n";
  if (!files.errors.empty()) {
    std::cerr << cmd.graph_file.string() << ": invalid graph\n";
    for (const auto& e : files.errors) std::cerr << "error: " << e << "\n";
    return kExitInvalid;
  }
  const std::size_t warnings = loaded.warnings.size() + files.warnings.size();
  std::cout << cmd.graph_file.string() << ": valid (" << node_count << " nodes"
            << (graph.nodes().size() == node_count
                    ? std::string()
                    : ", " + std::to_string(graph.nodes().size()) + " with subgraphs expanded")
            << (warnings == 0 ? "" : ", " + std::to_string(warnings) + " warning(s)") << ")\n";
  return kExitOk;
}

}  // namespace orogen::cli
