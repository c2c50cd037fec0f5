// DrainageMetrics across the tiles of a tiled or distributed build, exact (graph/tile_graph.h, docs/distributed.md):
// the Strahler map bit for bit and the same report, figure for figure. The rounds go in phases, each message and
// answer tagged with its phase:
//
//  - spill: the spill graphs of all tiles (Barnes 2016, nodes/hydrology/tile_fill.h): the flat levels, so the raised
//    cells (depressions) on every tile;
//  - depressions: each tile labels its raised components with their deepest water (double, as the whole-domain node)
//    and owned cells; the solve joins them through shared samples, counts the depressions and keeps as lakes those
//    deep and large enough;
//  - epsilon: rounds of the epsilon surface until no perimeter value falls;
//  - ring: the one-sample ring of the filled surface and of the input from the tiles around (tile_ring.h): D8
//    directions as on the whole domain, and the pits (interior cells without a lower neighbor in the input);
//  - accumulation: D8 cell counts through perimeter links (Barnes 2017); the area is count x cell area;
//  - Strahler: donor summaries at the perimeters until none changes (tile_strahler.h);
//  - main-stream length: the longest flow path from the divide, max(donor's + step), through the perimeters until
//    none changes (a max of sums computed one step at a time, as on the whole domain, so exact);
//  - network: each tile sends its channel cells and its pit and lake-cell counts; the solve orders the channel cells
//    as the whole-domain stack order restricted to them and computes the figures with the whole-domain code
//    (network_figures), sums in the same order. Every tile gets the report.
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "graph/node_type.h"
#include "graph/tile_bytes.h"
#include "graph/tile_graph.h"
#include "nodes/common/report_builder.h"
#include "nodes/hydrology/channel_network.h"
#include "nodes/hydrology/depressions.h"
#include "nodes/hydrology/drainage_metrics.h"
#include "nodes/hydrology/tile_accumulation.h"
#include "nodes/hydrology/tile_components.h"
#include "nodes/hydrology/tile_fill.h"
#include "nodes/hydrology/tile_phases.h"
#include "nodes/hydrology/tile_ring.h"
#include "nodes/hydrology/tile_strahler.h"

namespace orogen::hydrology {
namespace {

enum class Phase : std::uint8_t { Spill, Depressions, Epsilon, Ring, Accumulate, Strahler, Longest, Network, Done };

constexpr const char* kWhat = "drainage metrics across tiles";

constexpr const char* kWho = "drainage metrics";  // starts the error messages

Phase take_phase(std::string_view& bytes) { return hydrology::take_phase<Phase>(bytes, kWhat, kWho); }

void expect_end(std::string_view in) { hydrology::expect_end(in, kWho); }

void put_string(std::string& out, const std::string& s) {
  bytes::put_vector(out, std::vector<char>(s.begin(), s.end()));
}
std::string take_string(std::string_view& in) {
  const auto v = bytes::take_vector<char>(in, kWhat);
  return {v.begin(), v.end()};
}

// The longest flow path from the divide to every cell of a tile, through the other tiles' values at its perimeter.
class TileLongest {
 public:
  // `order`: the cells upstream first (upstream_first of the same receivers).
  TileLongest(std::vector<std::int32_t> receiver, std::vector<std::int32_t> order, std::vector<double> step,
              const TileRect& rect)
      : rect_(rect), receiver_(std::move(receiver)), order_(std::move(order)), step_(std::move(step)) {
    perimeter_ = perimeter_index(rect.size);
    const std::size_t n = perimeter_cells(rect.size).size();
    own_.assign(n, 0.0), external_.assign(n, 0.0), sent_.assign(n, -1.0);
    compute();
  }
  std::string message() {
    bool changed = false;
    for (std::size_t k = 0; k < own_.size(); ++k) changed = changed || own_[k] != sent_[k];
    sent_ = own_;
    std::string out;
    put_tile_rect(out, rect_);
    bytes::put(out, static_cast<std::uint8_t>(changed));
    bytes::put_vector(out, own_);
    return out;
  }
  void answer(std::string_view bytes) {
    auto external = bytes::take_vector<double>(bytes, kWhat);
    if (!bytes.empty() || external.size() != external_.size())
      throw std::invalid_argument("drainage metrics: one length per perimeter cell expected");
    external_ = std::move(external);
    compute();
  }
  const std::vector<double>& values() const { return value_; }

 private:
  void compute() {
    std::vector<double> partial(receiver_.size(), 0.0);
    value_.assign(receiver_.size(), 0.0);
    for (const std::int32_t c : order_) {
      const auto u = static_cast<std::size_t>(c);
      double v = partial[u];
      if (const std::int32_t p = perimeter_[u]; p >= 0) {
        own_[static_cast<std::size_t>(p)] = partial[u];
        v = std::max(v, external_[static_cast<std::size_t>(p)]);
      }
      value_[u] = v;
      if (const std::int32_t r = receiver_[u]; r >= 0)
        partial[static_cast<std::size_t>(r)] = std::max(partial[static_cast<std::size_t>(r)], v + step_[u]);
    }
  }

  TileRect rect_;
  std::vector<std::int32_t> receiver_, order_, perimeter_;
  std::vector<double> step_, own_, external_, sent_, value_;
};

// Every tile's perimeter lengths into the other tiles' largest at each of its perimeter cells.
std::vector<std::string> solve_longest(std::span<const std::string_view> messages, glm::ivec2 size) {
  struct Tile {
    TileRect rect;
    std::vector<double> own;
  };
  std::vector<Tile> tiles;
  std::unordered_map<std::int64_t, std::vector<std::pair<std::size_t, std::size_t>>> holders;
  for (std::string_view in : messages) {
    Tile t;
    t.rect = take_tile_rect(in, size, kWhat);
    bytes::take<std::uint8_t>(in, kWhat);
    t.own = bytes::take_vector<double>(in, kWhat);
    const auto cells = perimeter_cells(t.rect.size);
    if (!in.empty() || t.own.size() != cells.size())
      throw std::invalid_argument("drainage metrics: one length per perimeter cell expected");
    for (std::size_t k = 0; k < cells.size(); ++k)
      holders[domain_sample(t.rect, size, cells[k])].emplace_back(tiles.size(), k);
    tiles.push_back(std::move(t));
  }
  std::vector<std::string> answers(tiles.size());
  for (std::size_t t = 0; t < tiles.size(); ++t) {
    const auto cells = perimeter_cells(tiles[t].rect.size);
    std::vector<double> external(cells.size(), 0.0);
    for (std::size_t k = 0; k < cells.size(); ++k)
      for (const auto& [u, q] : holders.at(domain_sample(tiles[t].rect, size, cells[k])))
        if (u != t) external[k] = std::max(external[k], tiles[u].own[q]);
    bytes::put_vector(answers[t], external);
  }
  return answers;
}

bool longest_changed(std::span<const std::string_view> messages) {
  for (std::string_view in : messages) {
    for (int k = 0; k < 4; ++k) bytes::take<int>(in, kWhat);
    if (bytes::take<std::uint8_t>(in, kWhat)) return true;
  }
  return false;
}

struct ChannelCell {
  std::int64_t sample;
  std::int64_t count;
  double longest;
  float z;
  std::int32_t order;
  std::uint8_t direction;
  std::uint8_t lake;  // nonzero in a depression: left out of the slope-area fit
  // Zeroed and explicit, not packed: the cells travel as bytes, and packed members would be misaligned in memory.
  std::uint8_t padding[6]{};
};
static_assert(sizeof(ChannelCell) == 40, "no padding beyond the explicit bytes");

struct Params {
  double threshold = 1e5;
  LakeThreshold lake;
};

class DrainageTile : public TileGraphTile {
 public:
  DrainageTile(const Heightfield& ground, const Domain& whole, const Params& p)
      : domain_(ground.domain), size_(whole.resolution), grid_(FlowGrid::of(whole)), params_(p) {
    rect_ = {domain_.first, domain_.resolution};
    ground_ = ground.data;
    flood_ = flood_tile(ground_, rect_);
  }

  std::string message(int) override {
    switch (phase_) {
      case Phase::Spill:
        return tagged(phase_, encode(flood_.graph));
      case Phase::Depressions: {
        std::string out;
        put_tile_rect(out, rect_);
        bytes::put_vector(out, depth_);
        bytes::put_vector(out, cells_);
        std::vector<std::int32_t> perimeter;
        for (const std::int32_t c : perimeter_cells(rect_.size))
          perimeter.push_back(label_[static_cast<std::size_t>(c)]);
        bytes::put_vector(out, perimeter);
        return tagged(phase_, std::move(out));
      }
      case Phase::Epsilon:
        return tagged(phase_, epsilon_->message());
      case Phase::Ring:
        return tagged(phase_, ring_pair_message(surface_, ground_, rect_));
      case Phase::Accumulate:
        return tagged(phase_, accumulation_message(accumulation_));
      case Phase::Strahler:
        return tagged(phase_, strahler_->message());
      case Phase::Longest:
        return tagged(phase_, longest_->message());
      case Phase::Network:
        return tagged(phase_, network_message());
      case Phase::Done:
        break;
    }
    throw std::logic_error("drainage metrics: a message after the last round");
  }

  void answer(int, std::string_view bytes) override {
    const Phase next = take_phase(bytes);
    switch (phase_) {
      case Phase::Spill: {
        flat_ = apply_spill_levels(flood_, bytes::take_vector<float>(bytes, kWhat));
        expect_end(bytes);
        flood_ = {};
        label_depressions();
        break;
      }
      case Phase::Depressions: {
        const auto kept = bytes::take_vector<std::uint8_t>(bytes, kWhat);
        depressions_ = bytes::take<std::int64_t>(bytes, kWhat);
        lakes_ = bytes::take<std::int64_t>(bytes, kWhat);
        expect_end(bytes);
        if (kept.size() != depth_.size()) throw std::invalid_argument("drainage metrics: one flag per depression");
        lake_.assign(label_.size(), 0);
        for (std::size_t c = 0; c < label_.size(); ++c)
          if (label_[c]) lake_[c] = kept[static_cast<std::size_t>(label_[c] - 1)] ? 2 : 1;
        label_ = {};
        epsilon_ = std::make_unique<TileEpsilon>(std::move(flat_), rect_, size_);
        break;
      }
      case Phase::Epsilon:
        epsilon_->answer(bytes);
        if (next != Phase::Epsilon) {
          surface_ = epsilon_->surface();
          epsilon_.reset();
        }
        break;
      case Phase::Ring: {
        const auto [filled, input] = with_ring_pair(surface_, ground_, rect_, size_, bytes);
        take_rings(filled, input);
        break;
      }
      case Phase::Accumulate: {
        counts_ = finish_tile_accumulation(accumulation_, bytes);
        strahler_ = std::make_unique<TileStrahler>(
            accumulation_.receiver, channel_cells(counts_, grid_.cell_area(), params_.threshold), rect_, size_);
        break;
      }
      case Phase::Strahler:
        strahler_->answer(bytes);
        if (next != Phase::Strahler) {
          std::vector<double> step(direction_.size(), 0.0);
          for (std::size_t c = 0; c < step.size(); ++c)
            if (direction_[c] != kNoDirection) step[c] = grid_.distance(direction_[c]);
          longest_ = std::make_unique<TileLongest>(accumulation_.receiver,
                                                   upstream_first(accumulation_.receiver, "drainage metrics"),
                                                   std::move(step), rect_);
        }
        break;
      case Phase::Longest:
        longest_->answer(bytes);
        break;
      case Phase::Network:
        report_ = take_string(bytes);
        expect_end(bytes);
        break;
      case Phase::Done:
        throw std::logic_error("drainage metrics: an answer after the last round");
    }
    phase_ = next;
  }

  std::vector<PortValue> outputs() override {
    if (phase_ != Phase::Done) throw std::logic_error("drainage metrics: outputs before the last round");
    auto order = std::make_shared<Heightfield>(domain_);
    const auto& cells = strahler_->cells();
    const auto& o = strahler_->orders();
    for (std::size_t k = 0; k < cells.size(); ++k)
      order->data[static_cast<std::size_t>(cells[k])] = static_cast<float>(o[k]);
    return {HeightfieldPtr(order), ReportPtr(make_report(report_))};
  }

 private:
  // Raised cells' components with their deepest water and the cells the tile owns (as the whole-domain node).
  void label_depressions() {
    std::vector<std::uint8_t> raised(flat_.size());
    for (std::size_t c = 0; c < flat_.size(); ++c) raised[c] = flat_[c] > ground_[c];
    const int count = label_components(rect_.size.x, rect_.size.y, raised, label_);
    depth_.assign(static_cast<std::size_t>(count), 0.0);
    cells_.assign(static_cast<std::size_t>(count), 0);
    const int owned_x = rect_.first.x + rect_.size.x == size_.x ? rect_.size.x : rect_.size.x - 1;
    const int owned_y = rect_.first.y + rect_.size.y == size_.y ? rect_.size.y : rect_.size.y - 1;
    for (int j = 0; j < rect_.size.y; ++j)
      for (int i = 0; i < rect_.size.x; ++i) {
        const std::size_t c = static_cast<std::size_t>(j) * static_cast<std::size_t>(rect_.size.x) + i;
        if (!label_[c]) continue;
        const auto k = static_cast<std::size_t>(label_[c] - 1);
        depth_[k] = std::max(depth_[k], static_cast<double>(flat_[c]) - ground_[c]);
        if (i < owned_x && j < owned_y) ++cells_[k];
      }
  }

  // `z` and `in`: the filled surface and the input heights with their rings (ringed_rect).
  void take_rings(const std::vector<float>& z, const std::vector<float>& in) {
    const TileRect ringed = ringed_rect(rect_, size_);
    const FlowGrid g(ringed.size.x, ringed.size.y, grid_.dx, grid_.dy);
    direction_ = without_ring<std::uint8_t>(d8_flow(g, z).direction, rect_, size_);
    accumulation_ = start_tile_accumulation(direction_, rect_, size_);
    const glm::ivec2 at = rect_.first - ringed.first;
    // Pits among the interior cells the tile owns, and lake cells.
    for (int j = 0; j < rect_.size.y; ++j)
      for (int i = 0; i < rect_.size.x; ++i) {
        const std::size_t c = static_cast<std::size_t>(j) * static_cast<std::size_t>(rect_.size.x) + i;
        if (!accumulation_.owned[c]) continue;
        lake_cells_ += lake_[c] == 2;
        const int gi = rect_.first.x + i, gj = rect_.first.y + j;
        if (gi < 1 || gj < 1 || gi > size_.x - 2 || gj > size_.y - 2) continue;
        const std::int32_t r = g.index(at.x + i, at.y + j);
        bool lower = false;
        for (int k = 0; k < 8 && !lower; ++k)
          lower = in[static_cast<std::size_t>(r + g.offset(k))] < in[static_cast<std::size_t>(r)];
        pits_ += !lower;
        pits_outside_ += !lower && lake_[c] != 2;
      }
  }

  std::string network_message() const {
    std::vector<ChannelCell> cells;
    const auto& channel = strahler_->cells();
    const auto& order = strahler_->orders();
    const auto& longest = longest_->values();
    for (std::size_t k = 0; k < channel.size(); ++k) {
      const auto c = static_cast<std::size_t>(channel[k]);
      if (!accumulation_.owned[c]) continue;
      const int i = static_cast<int>(c) % rect_.size.x, j = static_cast<int>(c) / rect_.size.x;
      cells.push_back({static_cast<std::int64_t>(rect_.first.y + j) * size_.x + rect_.first.x + i, counts_[c],
                       longest[c], surface_[c], order[k], direction_[c], lake_[c]});
    }
    std::string out;
    bytes::put(out, depressions_), bytes::put(out, lakes_);
    bytes::put(out, pits_), bytes::put(out, pits_outside_), bytes::put(out, lake_cells_);
    bytes::put_vector(out, cells);
    return out;
  }

  Domain domain_;
  glm::ivec2 size_;
  FlowGrid grid_;
  Params params_;
  TileRect rect_;
  Phase phase_ = Phase::Spill;
  std::vector<float> ground_, flat_, surface_;
  TileFlood flood_;
  std::vector<std::int32_t> label_;
  std::vector<double> depth_;
  std::vector<std::int64_t> cells_;
  std::vector<std::uint8_t> lake_, direction_;
  std::unique_ptr<TileEpsilon> epsilon_;
  TileAccumulation accumulation_;
  std::vector<std::int64_t> counts_;
  std::unique_ptr<TileStrahler> strahler_;
  std::unique_ptr<TileLongest> longest_;
  std::int64_t depressions_ = 0, lakes_ = 0;                   // of the whole domain
  std::int64_t pits_ = 0, pits_outside_ = 0, lake_cells_ = 0;  // of the cells this tile owns
  std::string report_;
};

class DrainageAcrossTiles : public TileGraphAlgorithm {
 public:
  DrainageAcrossTiles(const Params& p, const Domain& whole) : params_(p), whole_(whole) {}

  int rounds() const override { return 1; }

  bool another_round(int, const std::vector<std::string>& messages) const override {
    if (messages.empty()) return false;
    std::string_view first(messages.front());
    return take_phase(first) != Phase::Network;
  }

  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    const auto* ground = inputs.empty() ? nullptr : std::get_if<HeightfieldPtr>(&inputs[0]);
    if (!ground || !*ground) throw std::invalid_argument("drainage metrics across tiles need a heightfield input");
    return std::make_unique<DrainageTile>(**ground, whole_, params_);
  }

  std::vector<std::string> solve(int, const std::vector<std::string>& tagged_messages) const override {
    const auto [phase, messages] = untag_messages<Phase>(tagged_messages, kWhat, kWho);
    const glm::ivec2 size = whole_.resolution;
    std::vector<std::string> answers(messages.size());
    Phase next = Phase::Done;
    switch (phase) {
      case Phase::Spill: {
        answers = solve_spill_messages(messages, size);
        next = Phase::Depressions;
        break;
      }
      case Phase::Depressions:
        answers = solve_depressions(messages);
        next = Phase::Epsilon;
        break;
      case Phase::Epsilon:
        answers = solve_perimeter_minima(messages, size);
        next = perimeter_minima_fell(messages) ? Phase::Epsilon : Phase::Ring;
        break;
      case Phase::Ring:
        answers = solve_ring_pairs(messages, size);
        next = Phase::Accumulate;
        break;
      case Phase::Accumulate:
        answers = solve_tile_accumulation(messages, size);
        next = Phase::Strahler;
        break;
      case Phase::Strahler:
        answers = solve_strahler_perimeters(messages, size);
        next = strahler_changed(messages) ? Phase::Strahler : Phase::Longest;
        break;
      case Phase::Longest:
        answers = solve_longest(messages, size);
        next = longest_changed(messages) ? Phase::Longest : Phase::Network;
        break;
      case Phase::Network: {
        std::string report;
        put_string(report, report_json(messages));
        std::fill(answers.begin(), answers.end(), report);
        break;
      }
      case Phase::Done:
        throw std::invalid_argument("drainage metrics: a message after the last round");
    }
    for (auto& a : answers) a = tagged(next, std::move(a));
    return answers;
  }

 private:
  std::vector<std::string> solve_depressions(std::span<const std::string_view> messages) const {
    const glm::ivec2 size = whole_.resolution;
    struct Tile {
      TileRect rect;
      std::vector<double> depth;
      std::vector<std::int64_t> cells;
      std::vector<std::int32_t> perimeter;
    };
    std::vector<Tile> tiles;
    std::vector<std::int32_t> offset{0};
    for (std::string_view in : messages) {
      Tile t;
      t.rect = take_tile_rect(in, size, kWhat);
      t.depth = bytes::take_vector<double>(in, kWhat);
      t.cells = bytes::take_vector<std::int64_t>(in, kWhat);
      t.perimeter = bytes::take_vector<std::int32_t>(in, kWhat);
      if (!in.empty() || t.cells.size() != t.depth.size() || t.depth.size() > (std::size_t(1) << 30) ||
          t.perimeter.size() != perimeter_cells(t.rect.size).size())
        throw std::invalid_argument("drainage metrics: malformed depressions");
      for (const std::int32_t k : t.perimeter)
        if (k < 0 || static_cast<std::size_t>(k) > t.depth.size())
          throw std::invalid_argument("drainage metrics: an unknown depression");
      offset.push_back(offset.back() + static_cast<std::int32_t>(t.depth.size()));
      tiles.push_back(std::move(t));
    }
    LowestRootUnionFind joined = join_numbered_components(
        tiles, size, offset, "drainage metrics: tiles disagree whether a shared sample is raised");
    const auto n = static_cast<std::size_t>(offset.back());
    std::vector<double> depth(n, 0.0);
    std::vector<std::int64_t> cells(n, 0);
    for (std::size_t t = 0; t < tiles.size(); ++t)
      for (std::size_t k = 0; k < tiles[t].depth.size(); ++k) {
        const auto root = static_cast<std::size_t>(joined.root(offset[t] + static_cast<std::int32_t>(k)));
        depth[root] = std::max(depth[root], tiles[t].depth[k]);
        cells[root] += tiles[t].cells[k];
      }
    // As drainage_metrics: a lake is deep and large enough.
    const double cell_area = whole_.spacing.x * whole_.spacing.y;
    std::vector<std::uint8_t> kept(n, 0);
    std::int64_t depressions = 0, lakes = 0;
    for (std::size_t c = 0; c < n; ++c)
      if (joined.root(static_cast<std::int32_t>(c)) == static_cast<std::int32_t>(c)) {
        ++depressions;
        kept[c] = depth[c] >= params_.lake.depth && static_cast<double>(cells[c]) * cell_area >= params_.lake.area;
        lakes += kept[c];
      }
    std::vector<std::string> answers(tiles.size());
    for (std::size_t t = 0; t < tiles.size(); ++t) {
      std::vector<std::uint8_t> flags(tiles[t].depth.size());
      for (std::size_t k = 0; k < flags.size(); ++k)
        flags[k] = kept[static_cast<std::size_t>(joined.root(offset[t] + static_cast<std::int32_t>(k)))];
      bytes::put_vector(answers[t], flags);
      bytes::put(answers[t], depressions), bytes::put(answers[t], lakes);
    }
    return answers;
  }

  // The report from every tile's channel cells and counts, as drainage_metrics writes it.
  std::string report_json(std::span<const std::string_view> messages) const {
    std::int64_t depressions = 0, lakes = 0, pits = 0, pits_outside = 0, lake_cells = 0;
    std::vector<ChannelCell> cells;
    for (std::string_view in : messages) {
      depressions = bytes::take<std::int64_t>(in, kWhat);  // the whole domain's, alike in every tile
      lakes = bytes::take<std::int64_t>(in, kWhat);
      pits += bytes::take<std::int64_t>(in, kWhat);
      pits_outside += bytes::take<std::int64_t>(in, kWhat);
      lake_cells += bytes::take<std::int64_t>(in, kWhat);
      const auto part = bytes::take_vector<ChannelCell>(in, kWhat);
      expect_end(in);
      cells.insert(cells.end(), part.begin(), part.end());
    }
    const glm::ivec2 size = whole_.resolution;
    const FlowGrid g = FlowGrid::of(whole_);
    const std::int64_t samples = static_cast<std::int64_t>(size.x) * size.y;
    const ChannelNetwork net = sorted_channel_network(cells, size, "drainage metrics");
    const auto& receiver = net.receiver;
    const auto& donors = net.donors;
    const auto& order = net.order;
    // network_metrics' traversal over the channel cells, upstream first.
    NetworkSamples s;
    std::vector<std::int32_t> stream(cells.size(), -1);
    for (auto it = order.rbegin(); it != order.rend(); ++it) {
      const auto c = static_cast<std::size_t>(*it);
      const ChannelCell& cell = cells[c];
      std::int32_t same = -1;
      for (const auto& [k, d] : donors[c])
        if (cells[static_cast<std::size_t>(d)].order == cell.order) same = d;
      const bool drains = receiver[c] != static_cast<std::int32_t>(c);
      ChannelSample sample{same,
                           cell.order,
                           drains ? g.distance(cell.direction) : 0.0,
                           static_cast<double>(cell.count) * g.cell_area(),
                           cell.longest,
                           std::nullopt};
      if (drains && !cell.lake)
        sample.slope =
            (static_cast<double>(cell.z) - cells[static_cast<std::size_t>(receiver[c])].z) / g.distance(cell.direction);
      add_channel_sample(s, stream, c, sample);
    }
    DrainageReport r;
    r.threshold = params_.threshold;
    r.lake = params_.lake;
    const auto total = static_cast<std::size_t>(samples);
    const double per = 1e6 / static_cast<double>(std::max<std::size_t>(1, total));
    r.pits_per_million = static_cast<double>(pits) * per;
    r.pits_outside_lakes_per_million = static_cast<double>(pits_outside) * per;
    r.lake_cells_fraction = static_cast<double>(lake_cells) / static_cast<double>(std::max<std::size_t>(1, total));
    r.depressions = static_cast<std::size_t>(depressions);
    r.lakes = static_cast<std::size_t>(lakes);
    r.network = network_figures(s, total);
    return r.json();
  }

  Params params_;
  Domain whole_;
};

const bool kDrainageRegistered = register_tile_graph("DrainageMetrics", [](const ParamView& p, const Domain& whole) {
  Params params;
  params.threshold = p.get<double>("threshold");
  params.lake.depth = p.get<double>("lake_depth");
  params.lake.area = p.get<double>("lake_area");
  std::unique_ptr<TileGraphAlgorithm> algorithm = std::make_unique<DrainageAcrossTiles>(params, whole);
  return algorithm;
});

}  // namespace
}  // namespace orogen::hydrology
