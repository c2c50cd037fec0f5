#include "cli/tile_graph_stages.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "cli/stats_report.h"
#include "cli/tile_assignment.h"
#include "cli/tile_memory.h"
#include "evaluator/domain_crop.h"
#include "evaluator/node_keys.h"
#include "graph/sample_rect.h"
#include "graph/tile_bytes.h"
#include "graph/tile_graph.h"

namespace orogen::cli {
namespace {

// A raster output's samples as rows of `channels` floats a sample (a heightfield has one, an image its channels);
// data is null for an output that is not a raster (curves and reports: the same whole value on every tile). F is
// const float for a tile's own result, float for the outputs being put together.
template <class F>
struct Raster {
  F* data = nullptr;
  int channels = 0;
  Domain domain;
  F* row(int j) const {
    return data + static_cast<std::size_t>(j) * static_cast<std::size_t>(domain.resolution.x) *
                      static_cast<std::size_t>(channels);
  }
};

Raster<const float> raster_of(const PortValue& value) {
  if (const auto* h = std::get_if<HeightfieldPtr>(&value); h && *h) return {(*h)->data.data(), 1, (*h)->domain};
  if (const auto* i = std::get_if<ImagePtr>(&value); i && *i) return {(*i)->data.data(), (*i)->channels, (*i)->domain};
  return {};
}

// The samples of `rect` of every output of a tile's result, as one piece of an exchange: the tile they are for,
// the rectangle, then the values of each raster output.
void put_piece(std::string& out, long long for_tile, const SampleRect& rect, const std::vector<PortValue>& outputs,
               const Domain& whole) {
  bytes::put(out, static_cast<std::int64_t>(for_tile));
  bytes::put(out, rect);
  for (const auto& value : outputs) {
    const auto h = raster_of(value);
    if (!h.data) continue;
    const glm::ivec2 at = rect.lo - rect_of(h.domain, whole).lo;
    for (int j = 0; j <= rect.hi.y - rect.lo.y; ++j)
      out.append(reinterpret_cast<const char*>(h.row(at.y + j) + static_cast<std::size_t>(at.x) * h.channels),
                 static_cast<std::size_t>(rect.size().x) * static_cast<std::size_t>(h.channels) * sizeof(float));
  }
}

// Copies the samples `rect` of a tile's outputs into the outputs of a tile of the same rank being put together.
void copy_rect(const std::vector<PortValue>& from, const SampleRect& rect, const std::vector<Raster<float>>& into,
               const Domain& whole) {
  for (std::size_t o = 0; o < from.size(); ++o) {
    const auto src = raster_of(from[o]);
    const Raster<float>& dst = into[o];
    if (!src.data || !dst.data) continue;
    const glm::ivec2 s = rect.lo - rect_of(src.domain, whole).lo, d = rect.lo - rect_of(dst.domain, whole).lo;
    const std::size_t width = static_cast<std::size_t>(rect.size().x) * static_cast<std::size_t>(src.channels);
    for (int j = 0; j <= rect.hi.y - rect.lo.y; ++j)
      std::copy_n(src.row(s.y + j) + static_cast<std::size_t>(s.x) * src.channels, width,
                  dst.row(d.y + j) + static_cast<std::size_t>(d.x) * dst.channels);
  }
}

// Copies the samples `rect` of a piece into the tile's outputs being put together.
void take_piece(std::string_view& in, const SampleRect& rect, const std::vector<Raster<float>>& into,
                const Domain& whole) {
  for (const Raster<float>& h : into) {
    if (!h.data) continue;
    const glm::ivec2 at = rect.lo - rect_of(h.domain, whole).lo;
    const auto width = static_cast<std::size_t>(rect.size().x) * static_cast<std::size_t>(h.channels);
    for (int j = 0; j <= rect.hi.y - rect.lo.y; ++j) {
      if (in.size() < width * sizeof(float)) throw std::runtime_error("tile-graph exchange: truncated piece");
      std::memcpy(h.row(at.y + j) + static_cast<std::size_t>(at.x) * h.channels, in.data(), width * sizeof(float));
      in.remove_prefix(width * sizeof(float));
    }
  }
}

// An output of the tile being put together on domain d, shaped as the tile's own result `core`, and where its
// samples go (curves and reports are the tile's own: the same whole value on every tile).
std::pair<PortValue, Raster<float>> blank_like(const PortValue& core, const Domain& d) {
  if (std::holds_alternative<HeightfieldPtr>(core)) {
    auto h = std::make_shared<Heightfield>(d);
    Raster<float> r{h->data.data(), 1, d};
    return {HeightfieldPtr(std::move(h)), r};
  }
  if (const auto* i = std::get_if<ImagePtr>(&core); i && *i) {
    auto image = std::make_shared<Image>(d, (*i)->channels);
    image->channel_names = (*i)->channel_names;
    image->color = (*i)->color;
    Raster<float> r{image->data.data(), image->channels, d};
    return {ImagePtr(std::move(image)), r};
  }
  return {core, {}};
}

// Where a stage's time goes (rank 0's view), for its report.
struct Phases {
  double inputs = 0, tiles = 0, communication = 0, solve = 0, halos = 0, keeping = 0;
  int rounds = 0;
  // Every rank's `tiles` (on more than one rank): a rank that works less than the slowest waits in `communication`.
  double fewest_tiles = 0, most_tiles = 0;
};

class Stages {
 public:
  Stages(const TileGraphStages& s, Evaluator& evaluator, RankGroup& group, TileResultSpill& kept)
      : s_(s),
        graph_(*s.graph),
        evaluator_(evaluator),
        group_(group),
        kept_(kept),
        arena_(evaluator.options().threads > 0 ? evaluator.options().threads : tbb::task_arena::automatic) {
    const long long count = static_cast<long long>(s.counts.x) * s.counts.y;
    domains_.resize(static_cast<std::size_t>(count));
    for (long long k = 0; k < count; ++k) {
      const glm::ivec2 index(static_cast<int>(k % s.counts.x), static_cast<int>(k / s.counts.x));
      domains_[static_cast<std::size_t>(k)] =
          tile_node_domains(graph_, s.domain, tile_window(s.domain.resolution, s.counts, index), s.global, s.across);
    }
  }

  void run() {
    std::vector<std::string> order;
    for (const auto& id : graph_.topological_order())
      if (s_.across.count(id)) order.push_back(id);
    for (std::size_t n = 0; n < order.size(); ++n) {
      // What feeds the stages still to come stays in memory from one stage's input evaluations to the next (fBm
      // under five flow nodes is computed once a tile); everything else those evaluations compute is released.
      feeding_later_.clear();
      for (std::size_t later = n + 1; later < order.size(); ++later)
        for (const auto& [port, link] : graph_.at(order[later]).inputs) feeding_later_.insert(link.node);
      run_node(graph_.at(order[n]));
    }
  }

 private:
  long long number(glm::ivec2 index) const { return tile_number(s_.counts, index); }
  glm::ivec2 index_of(long long k) const {
    return {static_cast<int>(k % s_.counts.x), static_cast<int>(k / s_.counts.x)};
  }
  const Domain& node_domain(long long tile, const std::string& id) const {
    return domains_[static_cast<std::size_t>(tile)].at(id);
  }
  std::string tile_label(glm::ivec2 index) const {
    return (group_.size() > 1 ? "rank " + std::to_string(group_.rank()) + ": " : std::string()) + "tile " +
           std::to_string(index.x) + "," + std::to_string(index.y);
  }

  void run_node(const Node& node) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::size_t mine = s_.tiles.size();
    std::vector<CacheKey> keys(mine);
    std::vector<std::shared_ptr<const CachedResult>> found(mine);
    const std::vector<bool> needed = needed_outputs(node);
    bool missing = false;
    for (std::size_t t = 0; t < mine; ++t) {
      const long long k = number(s_.tiles[t]);
      keys[t] = compute_cache_keys(graph_, s_.domain, s_.output, domains_[static_cast<std::size_t>(k)]).at(node.id);
      found[t] = evaluator_.find_result(keys[t], *node.type, needed);
      missing = missing || !found[t];
    }
    if (!any_rank(group_, missing)) {
      for (std::size_t t = 0; t < mine; ++t) kept_.put(t, node.id, *found[t]);
      say(node, "cached on every tile", t0, 0, nullptr);
      return;
    }

    const std::vector<ParamValue> params = graph_.effective_params(node);
    const auto algorithm = tile_graph_for(node.type->name, ParamView(*node.type, params), s_.domain);
    if (!algorithm) throw std::logic_error("node '" + node.id + "' was planned across the tiles but has no algorithm");
    // The tiles' inputs one evaluation after another (each evaluation is parallel), then their steps side by
    // side: tiles are independent between two solves.
    Phases phases;
    auto t_phase = std::chrono::steady_clock::now();
    auto lap = [&](double& into) {
      const auto now = std::chrono::steady_clock::now();
      into += std::chrono::duration<double, std::milli>(now - t_phase).count();
      t_phase = now;
    };
    std::vector<std::vector<PortValue>> inputs(mine);
    for (std::size_t t = 0; t < mine; ++t) inputs[t] = tile_inputs(node, t);
    lap(phases.inputs);
    std::vector<std::unique_ptr<TileGraphTile>> tiles(mine);
    each_tile([&](std::size_t t) {
      tiles[t] = algorithm->start(inputs[t]);
      tiles[t]->set_needed_outputs(needed);
      inputs[t].clear();
    });

    std::size_t exchanged = 0;
    for (int round = 0;; ++round) {
      // Ctrl+C between two rounds: every rank learns of it in the same round (an interrupted rank alone would leave
      // the others waiting in the exchange), so all of them stop there. A round is one step of the simulations.
      // The agreement waits for the slowest rank to take its answers in: that wait is communication, not tile work.
      lap(phases.tiles);
      const bool interrupted = any_rank(group_, s_.cancel && s_.cancel->cancelled());
      lap(phases.communication);
      if (interrupted)
        throw TileGraphStageError("interrupted in node '" + node.id + "' (" + node.type->name +
                                      ") across the tiles, at round " + std::to_string(round),
                                  true, true);
      std::vector<TilePart> parts(mine);
      each_tile([&](std::size_t t) { parts[t] = {number(s_.tiles[t]), tiles[t]->message(round)}; });
      for (const TilePart& part : parts) exchanged += part.bytes.size();
      lap(phases.tiles);
      std::vector<TilePart> all = gather_by_tile(group_, parts);
      lap(phases.communication);
      std::vector<std::string> messages(domains_.size());
      if (all.size() != messages.size()) throw std::runtime_error("tile-graph stage: a tile's message is missing");
      for (std::size_t k = 0; k < all.size(); ++k) {
        if (all[k].tile != static_cast<long long>(k)) throw std::runtime_error("tile-graph stage: tiles out of order");
        messages[k] = std::move(all[k].bytes);
      }
      const auto answers = algorithm->solve(round, messages);
      lap(phases.solve);
      each_tile(
          [&](std::size_t t) { tiles[t]->answer(round, answers[static_cast<std::size_t>(number(s_.tiles[t]))]); });
      ++phases.rounds;
      if (!algorithm->another_round(round, messages)) break;
    }
    std::vector<std::vector<PortValue>> cores(mine);
    each_tile([&](std::size_t t) {
      cores[t] = tiles[t]->outputs();
      tiles[t].reset();
      // Outputs nobody links are not kept (as the evaluator leaves them unset): they would only cost memory.
      for (std::size_t o = 0; o < cores[t].size() && o < needed.size(); ++o)
        if (!needed[o]) cores[t][o] = PortValue{};
    });
    lap(phases.tiles);
    auto results = put_together(node, cores);
    cores.clear();
    lap(phases.halos);
    // Each tile's result to the disk (the cache, and the spill the later evaluations read it from), not kept here.
    for (std::size_t t = 0; t < mine; ++t) {
      evaluator_.store_result(keys[t], results[t], false);
      kept_.put(t, node.id, *results[t]);
      results[t].reset();
    }
    lap(phases.keeping);
#ifdef __GLIBC__
    // The stage's round state was many blocks freed in a different order than they came: hand the free pages back,
    // so the next stage's peak is its own and not on top of this one's leftovers.
    malloc_trim(0);
#endif
    if (group_.size() > 1) {
      // Every rank's time in its tiles, so the report shows how evenly the assignment spread the work.
      std::string own;
      bytes::put(own, phases.tiles);
      phases.fewest_tiles = phases.most_tiles = phases.tiles;
      for (const std::string& rank : group_.all_gather(own)) {
        std::string_view in = rank;
        const double tiles = bytes::take<double>(in, "a rank's tile time");
        phases.fewest_tiles = std::min(phases.fewest_tiles, tiles);
        phases.most_tiles = std::max(phases.most_tiles, tiles);
      }
    }
    say(node, "computed across the tiles", t0, exchanged, &phases);
  }

  // fn(t) for every tile of this rank, in parallel on the evaluator's threads.
  template <class Fn>
  void each_tile(Fn&& fn) {
    arena_.execute([&] { tbb::parallel_for(std::size_t(0), s_.tiles.size(), [&](std::size_t t) { fn(t); }); });
  }

  // The node's inputs on exactly tile t's samples, from an evaluation of what feeds them on the tile.
  std::vector<PortValue> tile_inputs(const Node& node, std::size_t t) {
    const glm::ivec2 index = s_.tiles[t];
    const long long k = number(index);
    EvalRequest request;
    request.domain = s_.domain;
    request.node_domains = domains_[static_cast<std::size_t>(k)];
    request.cancel = s_.cancel;
    // Earlier stages' results upstream of the inputs, read back (the evaluation must not compute them on the tile).
    // An input fed by one of them directly is taken as it is (a requested node would owe every output).
    // Only the nearest ones: the evaluation stops at them, so those further up would be read for nothing.
    const std::set<std::string> done = kept_.nodes(t);
    const auto is_done = [&](const std::string& id) { return done.count(id) > 0; };
    for (const auto& id : graph_.upstream(node.id, is_done))
      if (is_done(id)) request.given_results[id] = kept_.get(t, id);
    for (const auto& [port, link] : node.inputs)
      if (!is_done(link.node) &&
          std::find(request.nodes.begin(), request.nodes.end(), link.node) == request.nodes.end())
        request.nodes.push_back(link.node);
    KeySet keep;
    if (!feeding_later_.empty()) {
      const auto keys = compute_cache_keys(graph_, s_.domain, s_.output, domains_[static_cast<std::size_t>(k)]);
      for (const auto& id : feeding_later_)
        if (const auto it = keys.find(id); it != keys.end()) keep.insert(it->second);
    }
    request.keep_in_memory = [&keep](const CacheKey& key) { return keep.count(key) > 0; };
    EvalResult result;
    if (!request.nodes.empty()) result = evaluator_.evaluate(graph_, request);
    if (result.cancelled) throw TileGraphStageError("interrupted in " + tile_label(index), true);
    for (const auto& [id, report] : result.nodes)
      if (report.status == NodeStatus::Failed)
        throw TileGraphStageError(tile_label(index) + ": node '" + id + "' failed: " + report.message, false);
    for (const auto& [id, report] : result.nodes)
      if (report.status == NodeStatus::Skipped)
        throw TileGraphStageError(tile_label(index) + ": node '" + id + "' skipped: " + report.message, false);
    const TileWindow w = tile_window(s_.domain.resolution, s_.counts, index);
    const Domain core = s_.domain.subdomain(w.first.x, w.first.y, w.size.x, w.size.y);
    std::vector<PortValue> inputs;
    for (const auto& port : node.type->inputs) {
      const auto it = node.inputs.find(port.name);
      if (it == node.inputs.end()) {
        inputs.emplace_back();
      } else if (const auto given = request.given_results.find(it->second.node); given != request.given_results.end()) {
        const ResolvedLink link = resolve_link(graph_, node, port);
        if (link.output < 0 || static_cast<std::size_t>(link.output) >= given->second->outputs.size())
          throw std::logic_error("tile-graph stage: input '" + port.name + "' of node '" + node.id + "' not found");
        inputs.push_back(crop_to_domain(given->second->outputs[static_cast<std::size_t>(link.output)], core));
      } else {
        inputs.push_back(crop_to_domain(result.output(it->second.node, it->second.port, graph_), core));
      }
    }
    return inputs;
  }

  // Every tile's result on the domain its evaluation needs: its own samples, and its consumers' halo from the
  // tiles around it, whichever rank holds them.
  std::vector<std::shared_ptr<const CachedResult>> put_together(const Node& node,
                                                                const std::vector<std::vector<PortValue>>& cores) {
    const std::size_t mine = s_.tiles.size();
    std::vector<std::vector<PortValue>> built(mine);
    std::vector<std::vector<Raster<float>>> samples(mine);  // where the built outputs' samples go
    for (std::size_t t = 0; t < mine; ++t) {
      const Domain& d = node_domain(number(s_.tiles[t]), node.id);
      for (const PortValue& core : cores[t]) {
        auto [value, raster] = blank_like(core, d);
        built[t].push_back(std::move(value));
        samples[t].push_back(raster);
      }
    }
    std::vector<std::string> outgoing(static_cast<std::size_t>(group_.size()));
    for (std::size_t t = 0; t < mine; ++t) {
      const TileWindow w = tile_window(s_.domain.resolution, s_.counts, s_.tiles[t]);
      const SampleRect core = rect_of(s_.domain.subdomain(w.first.x, w.first.y, w.size.x, w.size.y), s_.domain);
      for (std::size_t u = 0; u < domains_.size(); ++u) {
        const SampleRect part = overlap(core, rect_of(node_domain(static_cast<long long>(u), node.id), s_.domain));
        if (part.empty()) continue;
        const int owner = tile_owner(s_.counts, index_of(static_cast<long long>(u)), group_.size());
        if (owner == group_.rank()) {
          const auto to = std::find(s_.tiles.begin(), s_.tiles.end(), index_of(static_cast<long long>(u)));
          copy_rect(cores[t], part, samples[static_cast<std::size_t>(to - s_.tiles.begin())], s_.domain);
        } else {
          put_piece(outgoing[static_cast<std::size_t>(owner)], static_cast<long long>(u), part, cores[t], s_.domain);
        }
      }
    }
    for (const std::string& from : group_.exchange(outgoing)) {
      std::string_view in(from);
      while (!in.empty()) {
        const auto u = bytes::take<std::int64_t>(in, "tile-graph exchange");
        const auto part = bytes::take<SampleRect>(in, "tile-graph exchange");
        const auto it = std::find(s_.tiles.begin(), s_.tiles.end(), index_of(u));
        if (it == s_.tiles.end()) throw std::runtime_error("tile-graph exchange: a piece for a tile of another rank");
        take_piece(in, part, samples[static_cast<std::size_t>(it - s_.tiles.begin())], s_.domain);
      }
    }
    std::vector<std::shared_ptr<const CachedResult>> results(mine);
    for (std::size_t t = 0; t < mine; ++t) {
      auto r = std::make_shared<CachedResult>();
      r->outputs = std::move(built[t]);
      results[t] = std::move(r);
    }
    return results;
  }

  void say(const Node& node, const char* what, std::chrono::steady_clock::time_point t0, std::size_t exchanged,
           const Phases* phases) {
    if (s_.quiet || group_.rank() != 0) return;
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::fprintf(stderr, "node '%s' (%s) %s in %.1f ms", node.id.c_str(), node.type->name.c_str(), what, ms);
    if (phases) {
      std::fprintf(stderr, ": inputs %.0f ms, tiles %.0f ms", phases->inputs, phases->tiles);
      if (group_.size() > 1)
        std::fprintf(stderr, " (the ranks %.0f to %.0f ms)", phases->fewest_tiles, phases->most_tiles);
      std::fprintf(stderr,
                   ", messages %.0f ms (%d rounds, %.1f KiB from rank 0), solve %.0f "
                   "ms, halos %.0f ms, kept on disk %.0f ms",
                   phases->communication, phases->rounds, exchanged / 1024.0, phases->solve, phases->halos,
                   phases->keeping);
    }
    std::fprintf(stderr, "; resident %.0f MiB, peak %.0f MiB\n", resident_memory_bytes() / 1048576.0,
                 peak_memory_bytes() / 1048576.0);
  }

  // Per output of `node`: whether the build uses it (a link, a Report output, or any output of a node nothing
  // links: the evaluator's rule for requested nodes).
  // The links are resolved as the evaluator resolves them; a subgraph instance's inner node keeps all its outputs
  // (what its instance presents is the instance's business).
  std::vector<bool> needed_outputs(const Node& node) const {
    std::vector<bool> needed(node.type->outputs.size(), false);
    bool linked = false;
    for (const auto& other : graph_.nodes())
      for (const auto& port : other.type->inputs) {
        const ResolvedLink link = resolve_link(graph_, other, port);
        if (link.source == &node && link.output >= 0 && static_cast<std::size_t>(link.output) < needed.size())
          needed[static_cast<std::size_t>(link.output)] = linked = true;
      }
    const bool inner = node.id.find('/') != std::string::npos;
    for (std::size_t o = 0; o < needed.size(); ++o)
      needed[o] = needed[o] || !linked || inner || node.type->outputs[o].type == PortType::Report;
    return needed;
  }

  const TileGraphStages& s_;
  const Graph& graph_;
  Evaluator& evaluator_;
  RankGroup& group_;
  TileResultSpill& kept_;                               // every stage's results on this rank's tiles
  std::vector<std::map<std::string, Domain>> domains_;  // per tile of the tiling: every node's domain
  std::set<std::string> feeding_later_;                 // nodes linked to a stage after the current one
  tbb::task_arena arena_;
};

}  // namespace

void run_tile_graph_stages(const TileGraphStages& stages, Evaluator& evaluator, RankGroup& group,
                           TileResultSpill& kept) {
  if (!stages.across.empty()) Stages(stages, evaluator, group, kept).run();
}

}  // namespace orogen::cli
