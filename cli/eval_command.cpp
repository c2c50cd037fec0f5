#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <iostream>

#include "cli/commands.h"
#include "cli/graph_overrides.h"
#include "cli/progress_display.h"
#include "cli/stats_report.h"
#include "evaluator/evaluator.h"
#include "evaluator/memory_estimate.h"
#include "graph/atomic_file.h"
#include "graph/graph_file.h"

namespace orogen::cli {
namespace {

CancelToken g_interrupt;  // set by SIGINT/SIGTERM; CancelToken is a lock-free atomic, safe in a handler

extern "C" void on_interrupt(int) { g_interrupt.cancel(); }

}  // namespace

int run_eval(const EvalCommand& cmd) {
  auto loaded = load_graph_file(cmd.graph_file);
  if (!loaded.ok()) {
    std::cerr << cmd.graph_file.string() << ": invalid graph\n" << loaded.error_text();
    return kExitInvalid;
  }
  Graph graph = std::move(*loaded.graph);

  std::vector<std::string> errors = apply_param_overrides(graph, cmd.set);
  if (!cmd.resolution.empty()) {
    std::string why;
    if (auto r = resolution_for(cmd.resolution, graph.domain.size, why)) graph.domain.resolution = *r;
    else errors.push_back(why);
  }
  OutputPolicy policy{cmd.output_dir, cmd.allow_any_path};
  for (auto& e : check_output_paths(graph, policy)) errors.push_back(std::move(e));
  const auto cache_mb = parse_number(cmd.cache_mb, 0.0, 1e9);
  if (!cache_mb) errors.push_back("--cache-mb '" + cmd.cache_mb + "': expected a number of MiB from 0 to 1e9");
  const auto cache_disk_mb = parse_number(cmd.cache_disk_mb, 0.0, 1e9);
  if (!cache_disk_mb)
    errors.push_back("--cache-disk-mb '" + cmd.cache_disk_mb + "': expected a number of MiB from 0 to 1e9");
  std::uint64_t max_memory = available_memory_bytes();
  if (!cmd.max_memory.empty()) {
    if (auto m = parse_memory_size(cmd.max_memory); m && *m > 0) max_memory = *m;
    else errors.push_back("--max-memory '" + cmd.max_memory + "': expected a positive size such as 4096, 512M or 8G");
  }
  const Domain domain = graph.domain.to_domain();
  if (auto why = check_domain(domain); !why.empty()) errors.push_back(why);
  if (errors.empty() && max_memory > 0) {
    for (const auto& node : graph.nodes()) {
      const auto need = estimate_node_bytes(*node.type, domain);
      if (need > max_memory) errors.push_back("node '" + node.id + "': " + memory_refusal(*node.type, domain, need, max_memory));
    }
  }
  if (!errors.empty()) {
    for (const auto& e : errors) std::cerr << "error: " << e << "\n";
    return kExitInvalid;
  }

  EvaluatorOptions options;
  options.threads = cmd.threads;
  options.cache_bytes = static_cast<std::size_t>(*cache_mb * 1024.0 * 1024.0);
  options.cache_dir = cmd.cache_dir;
  options.cache_disk_bytes = static_cast<std::uint64_t>(*cache_disk_mb * 1024.0 * 1024.0);
  options.max_memory = max_memory;
  // Temporaries a killed run left in the output directory (the cache sweeps its own directory).
  remove_stale_temporaries(cmd.output_dir, 16);
  options.output = policy;
  Evaluator evaluator(options);

  EvalRequest request;
  request.domain = graph.domain.to_domain();
  request.cancel = &g_interrupt;
  const bool live = !cmd.quiet && ::isatty(STDERR_FILENO);
  ProgressDisplay display(stderr, graph.nodes().size());
  if (live) request.on_event = [&](const EvalEvent& e) { display.on_event(e); };

  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  const EvalResult result = evaluator.evaluate(graph, request);
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (live) display.finish();

  if (!cmd.stats_file.empty()) {
    try {
      write_text_atomically(cmd.stats_file, stats_json(result, &graph));
    } catch (const std::exception& e) {
      std::cerr << "error: cannot write stats to " << cmd.stats_file.string() << ": " << e.what() << "\n";
      return kExitEvalFailed;
    }
  }

  std::size_t computed = 0, cached = 0, failed = 0, skipped = 0;
  for (const auto& [id, r] : result.nodes) {
    switch (r.status) {
      case NodeStatus::Computed: ++computed; break;
      case NodeStatus::Cached: ++cached; break;
      case NodeStatus::Failed:
        ++failed;
        std::cerr << "error: node '" << id << "' failed: " << r.message << "\n";
        break;
      case NodeStatus::Skipped: ++skipped; break;
      default: break;
    }
  }
  if (result.cancelled) {
    std::cerr << "interrupted: nothing partial was written or cached\n";
    return kExitEvalFailed;
  }
  if (!cmd.quiet) {
    std::fprintf(stderr, "%zu computed, %zu cached, %zu failed, %zu skipped in %.1f ms\n", computed, cached, failed,
                 skipped, result.milliseconds);
  }
  return failed == 0 ? kExitOk : kExitEvalFailed;
}

int run_validate(const ValidateCommand& cmd) {
  auto loaded = load_graph_file(cmd.graph_file);
  if (!loaded.ok()) {
    std::cerr << cmd.graph_file.string() << ": invalid graph\n" << loaded.error_text();
    return kExitInvalid;
  }
  const FileCheck files = check_files(*loaded.graph, OutputPolicy{cmd.output_dir, cmd.allow_any_path});
  for (const auto& w : files.warnings) std::cerr << "warning: " << w << "\n";
  if (!files.errors.empty()) {
    std::cerr << cmd.graph_file.string() << ": invalid graph\n";
    for (const auto& e : files.errors) std::cerr << "error: " << e << "\n";
    return kExitInvalid;
  }
  std::cout << cmd.graph_file.string() << ": valid (" << loaded.graph->nodes().size() << " nodes"
            << (files.warnings.empty() ? "" : ", " + std::to_string(files.warnings.size()) + " warning(s)") << ")\n";
  return kExitOk;
}

}  // namespace orogen::cli
