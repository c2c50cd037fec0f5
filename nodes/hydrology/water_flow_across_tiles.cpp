// WaterFlow across the tiles of a tiled or distributed build, exact (graph/tile_graph.h): each tile iterates on its
// own samples with a halo of water depths taken from its neighbors' border bands every k iterations.
//
// One iteration reads the water within 2 samples (nodes/hydrology/water_flow_step.h), so k iterations need a halo of
// 2k: a tile runs iteration i of a block of k on itself grown by 2 (k - 1 - i) samples (its spread by one more), and
// after the block its own samples are exact. Round 0 settles k (the same for every tile, from the smallest tile);
// round 1 exchanges the bands of what does not change (the heights and the linked rainfall and sinks, from which each
// tile sets its halo's initial water and drains); round r >= 2 runs block r - 2 on every tile and exchanges the new
// water bands (doubles, as two 4-byte channels: low and high words) with each tile's exact sum of the water its own
// samples sent in each iteration. Every sum over the domain is exact (nodes/common/exact_double_sum.h), as in the
// whole-domain run, so the tiles' partial sums give its bits; a shared border sample is counted by the tile below or
// left of it only. Every tile sees every message, so all stop after the iteration the whole-domain run stops after
// (the first that moves nothing, whose effect is nil and is not counted, or that moves less than `threshold` of all
// moved so far, or the last of max_iterations): a tile that ran past it goes back to the block's start and runs again
// to it. One last round sums the report's rain, stored water, border outflow and sink inflow over the tiles.
#include "nodes/hydrology/water_flow_across_tiles.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "graph/node_type.h"
#include "graph/report.h"
#include "graph/tile_bytes.h"
#include "graph/tile_graph.h"
#include "nodes/common/exact_double_sum.h"
#include "nodes/common/finite_inputs.h"
#include "nodes/common/report_builder.h"
#include "nodes/common/work_bounds.h"
#include "nodes/erosion/tile_bands.h"
#include "nodes/hydrology/flow_routing.h"
#include "nodes/hydrology/water_flow_step.h"

namespace orogen::hydrology {
namespace {

using erosion::BandCells;
using erosion::Bands;
using erosion::for_each_halo;

constexpr int kReach = 2;  // one iteration reads the water within 2 samples

// A message: the tile's rectangle, the width of its bands, its 4-byte channels of bands, whether it is the last
// round's, the iterations run before this round and in it, and how many exact sums follow; then the sums (a block
// round: the run's total moved before the block, then the tile's moved in each iteration of the block; the last
// round: the tile's rain, stored water, border outflow and sink inflow), then each channel's bands.
struct Header {
  SampleRect rect;
  std::int32_t width = 0, channels = 0, last = 0, done = 0, ran = 0;
  std::vector<ExactDoubleSum> sums;
  std::size_t bytes() const {
    return sizeof(SampleRect) + 6 * sizeof(std::int32_t) + sums.size() * ExactDoubleSum::kBytes;
  }
};

void put_header(std::string& out, const Header& h) {
  bytes::put(out, h.rect);
  for (const std::int32_t v : {h.width, h.channels, h.last, h.done, h.ran, static_cast<std::int32_t>(h.sums.size())})
    bytes::put(out, v);
  for (const ExactDoubleSum& s : h.sums) s.put(out);
}

Header take_header(std::string_view in) {
  const char* what = "water flow bands";
  Header h;
  h.rect = bytes::take<SampleRect>(in, what);
  h.width = bytes::take<std::int32_t>(in, what), h.channels = bytes::take<std::int32_t>(in, what);
  h.last = bytes::take<std::int32_t>(in, what), h.done = bytes::take<std::int32_t>(in, what);
  h.ran = bytes::take<std::int32_t>(in, what);
  const auto sums = bytes::take<std::int32_t>(in, what);
  if (sums < 0 || static_cast<std::size_t>(sums) > in.size() / ExactDoubleSum::kBytes)
    throw std::invalid_argument("water flow bands: truncated bytes");
  h.sums.resize(static_cast<std::size_t>(sums));
  for (ExactDoubleSum& s : h.sums) s.take(in);
  return h;
}

// The outcome of a block over all tiles: the iterations of it the run keeps, whether the run stops after them, and
// the total moved after them.
struct Verdict {
  std::int32_t keep = 0;
  bool stop = false;
  ExactDoubleSum total;
};

std::string sum_bytes(const ExactDoubleSum& s) {
  std::string b;
  s.put(b);
  return b;
}

class WaterTile : public TileGraphTile {
 public:
  WaterTile(HeightfieldPtr in, HeightfieldPtr rainfall, HeightfieldPtr sinks, const WaterFlowParams& p,
            const Domain& whole)
      : in_(std::move(in)),
        rainfall_(std::move(rainfall)),
        sinks_(std::move(sinks)),
        p_(p),
        whole_domain_(whole),
        whole_(whole.resolution),
        rect_(rect_of(in_->domain, whole)) {
    // Shared border samples belong to the tile beyond them, unless they lie on the domain's far edge.
    own_hi_ = rect_.hi + glm::ivec2(rect_.hi.x == whole_.x - 1, rect_.hi.y == whole_.y - 1);
  }

  std::string message(int round) override {
    Header h;
    h.rect = rect_;
    h.width = halo_;
    h.done = done_;
    std::string out;
    if (round == 0) {
      put_header(out, h);
      return out;
    }
    if (finished_) {  // the last round: the report's sums
      h.last = 1;
      h.sums = {rain_, stored(), border_, sink_};
      put_header(out, h);
      return out;
    }
    if (round == 1) {
      std::vector<const std::vector<float>*> channels{&z_};
      if (!rain_grid_.empty()) channels.push_back(&rain_grid_);
      if (!sink_grid_.empty()) channels.push_back(&sink_grid_);
      h.channels = static_cast<std::int32_t>(channels.size());
      put_header(out, h);
      for (const auto* c : channels) cells_->bands.append(out, c->data());
      return out;
    }
    h.ran = std::min(block_, p_.max_iterations - done_);
    // Kept to go back to when the run stops inside the block (or, at its first iteration, moves nothing).
    w_start_ = grid_->w, flux_start_ = grid_->flux, border_start_ = border_, sink_start_ = sink_;
    h.sums.push_back(total_);
    for (int i = 0; i < h.ran; ++i) h.sums.push_back(iterate(h.ran - 1 - i));
    h.channels = 2;
    put_header(out, h);
    append_water(out);
    return out;
  }

  void answer(int round, std::string_view in) override {
    const char* what = "water flow halo";
    if (round == 0) {
      block_ = bytes::take<std::int32_t>(in, what);
      if (block_ < 1) throw std::invalid_argument("water flow halo: no iterations per exchange");
      start_grid();
    } else if (finished_) {
      rain_sum_ = bytes::take<double>(in, what), stored_sum_ = bytes::take<double>(in, what);
      border_sum_ = bytes::take<double>(in, what), sink_sum_ = bytes::take<double>(in, what);
    } else if (round == 1) {
      for (std::vector<float>* c : {&z_, &rain_grid_, &sink_grid_})
        if (!c->empty()) cells_->halo.take(in, c->data(), what);
      fill_grid();
    } else {
      const auto keep = bytes::take<std::int32_t>(in, what);
      const auto stop = bytes::take<std::int32_t>(in, what);
      if (!total_.take(in)) throw std::invalid_argument("water flow halo: truncated bytes");
      const int ran = std::min(block_, p_.max_iterations - done_);
      if (keep < 0 || keep > ran || (keep < ran && !stop)) throw std::invalid_argument("water flow halo: bad verdict");
      if (keep < ran) {
        // The run stopped inside the block: back to its start, and the kept iterations again.
        grid_->w = w_start_, grid_->flux = flux_start_, border_ = border_start_, sink_ = sink_start_;
        for (int i = 0; i < keep; ++i) iterate(keep - 1 - i);
      }
      done_ += keep;
      finished_ = stop != 0;
      if (!finished_) take_water(in);
    }
    if (!in.empty()) throw std::invalid_argument("water flow halo: bytes left over");
  }

  std::vector<PortValue> outputs() override {
    auto depth = std::make_shared<Heightfield>(in_->domain);
    auto flux = std::make_shared<Heightfield>(in_->domain);
    for (int j = 0; j < in_->height(); ++j)
      for (int i = 0; i < in_->width(); ++i) {
        const std::size_t q = cell(rect_.lo + glm::ivec2(i, j)), k = in_->index(i, j);
        depth->data[k] = static_cast<float>(std::max(0.0, grid_->w[q]));
        flux->data[k] = static_cast<float>(grid_->flux[q]);
      }
    WaterFlowResult r;
    r.rain = rain_sum_, r.stored = stored_sum_, r.border = border_sum_, r.sinks = sink_sum_;
    r.iterations = done_;
    return {HeightfieldPtr(depth), HeightfieldPtr(flux), ReportPtr(make_report(r.json()))};
  }

 private:
  // The grid: the tile grown by the halo of `block_` iterations, within the domain; the static fields on it from the
  // tile's own samples (the halo follows in round 1).
  void start_grid() {
    halo_ = kReach * block_;
    grid_lo_ = glm::max(rect_.lo - halo_, glm::ivec2(0));
    grid_size_ = glm::min(rect_.hi + halo_, whole_ - 1) - grid_lo_ + 1;
    const std::size_t n = static_cast<std::size_t>(grid_size_.x) * static_cast<std::size_t>(grid_size_.y);
    z_.assign(n, 0.0f);
    if (rainfall_) rain_grid_.assign(n, 0.0f);
    if (sinks_) sink_grid_.assign(n, 0.0f);
    for (int j = 0; j < in_->height(); ++j)
      for (int i = 0; i < in_->width(); ++i) {
        const std::size_t q = cell(rect_.lo + glm::ivec2(i, j)), k = in_->index(i, j);
        z_[q] = in_->data[k];
        if (rainfall_) rain_grid_[q] = rainfall_->data[k];
        if (sinks_) sink_grid_[q] = sinks_->data[k];
      }
    rainfall_.reset(), sinks_.reset();
    cells_.emplace(rect_, whole_, halo_, [&](glm::ivec2 s) { return cell(s); });
    for_each_halo(rect_, whole_, halo_, [&](glm::ivec2 s) { halo_cells_.push_back(cell(s)); });
    Bands(rect_, whole_, halo_).for_each([&](glm::ivec2 s) { band_cells_.push_back(cell(s)); });
  }

  // The initial water and the drains on the whole grid, as the whole-domain run sets them; the tile's own rain and
  // what its own drains take at once.
  void fill_grid() {
    const double area = FlowGrid::of(whole_domain_).cell_area();  // as the whole-domain run's
    grid_.emplace(grid_size_.x, grid_size_.y, area, z_.data());
    for (int j = 0; j < grid_size_.y; ++j)
      for (int i = 0; i < grid_size_.x; ++i) {
        const glm::ivec2 s = grid_lo_ + glm::ivec2(i, j);
        const std::size_t c = grid_->at(i, j);
        grid_->w[c] = water_initial_depth(rain_grid_.empty() ? p_.rainfall : rain_grid_[c], p_.infiltration);
        if (owns(s)) rain_.add(grid_->w[c] * area);
        const bool border = s.x == 0 || s.y == 0 || s.x == whole_.x - 1 || s.y == whole_.y - 1;
        grid_->drain[c] = border ? kBorderDrain : (!sink_grid_.empty() && sink_grid_[c] > 0.5f ? kSinkDrain : kNoDrain);
        if (grid_->drain[c]) drains_.push_back({c, owns(s)});
      }
    rain_grid_ = {}, sink_grid_ = {};
    empty_drains();
  }

  // One iteration on the tile grown by kReach x `later` samples (the iterations after it in the block); returns the
  // water the tile's own samples sent.
  ExactDoubleSum iterate(int later) {
    const int g = kReach * later;
    const glm::ivec2 lo = glm::max(rect_.lo - g - 1, glm::ivec2(0)) - grid_lo_,
                     hi = glm::min(rect_.hi + g + 1, whole_ - 1) - grid_lo_;
    const int s0 = rect_.lo.x - grid_lo_.x, s1 = own_hi_.x - grid_lo_.x;
    ExactDoubleSum moved, ignored;
    for (int j = lo.y; j <= hi.y; ++j) {
      const int y = j + grid_lo_.y;
      const bool own_row = y >= rect_.lo.y && y < own_hi_.y;
      water_spread_row(*grid_, j, lo.x, hi.x + 1, s0, s1, own_row ? moved : ignored);
    }
    const glm::ivec2 glo = glm::max(rect_.lo - g, glm::ivec2(0)) - grid_lo_,
                     ghi = glm::min(rect_.hi + g, whole_ - 1) - grid_lo_;
    for (int j = glo.y; j <= ghi.y; ++j) water_gather_row(*grid_, j, glo.x, ghi.x + 1);
    std::swap(grid_->w, grid_->next);
    empty_drains();
    return moved;
  }

  // Water on a drain leaves at once; the tile counts its own.
  void empty_drains() {
    for (const Drain& d : drains_) {
      if (d.own) (grid_->drain[d.cell] == kBorderDrain ? border_ : sink_).add(grid_->w[d.cell] * grid_->area);
      grid_->w[d.cell] = 0.0;
    }
  }

  ExactDoubleSum stored() const {
    ExactDoubleSum s;
    for (int y = rect_.lo.y; y < own_hi_.y; ++y)
      for (int x = rect_.lo.x; x < own_hi_.x; ++x) s.add(grid_->w[cell(glm::ivec2(x, y))] * grid_->area);
    return s;
  }

  // The water bands as two channels: the low and the high 32 bits of each depth.
  void append_water(std::string& out) const {
    for (const int word : {0, 1})
      for (const std::size_t c : band_cells_) bytes::put(out, half(grid_->w[c], word));
  }

  void take_water(std::string_view& in) {
    const char* what = "water flow halo";
    if (in.size() != 2 * halo_cells_.size() * sizeof(std::uint32_t))
      throw std::invalid_argument("water flow halo: truncated bytes");
    std::vector<std::uint32_t> low(halo_cells_.size());
    for (std::uint32_t& v : low) v = bytes::take<std::uint32_t>(in, what);
    for (std::size_t k = 0; k < halo_cells_.size(); ++k) {
      const std::uint64_t bits = (static_cast<std::uint64_t>(bytes::take<std::uint32_t>(in, what)) << 32) | low[k];
      std::memcpy(&grid_->w[halo_cells_[k]], &bits, sizeof bits);
    }
  }

  static std::uint32_t half(double v, int word) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    return static_cast<std::uint32_t>(bits >> (32 * word));
  }

  bool owns(glm::ivec2 s) const { return s.x >= rect_.lo.x && s.y >= rect_.lo.y && s.x < own_hi_.x && s.y < own_hi_.y; }

  std::size_t cell(glm::ivec2 s) const {
    return static_cast<std::size_t>(s.y - grid_lo_.y) * static_cast<std::size_t>(grid_size_.x) +
           static_cast<std::size_t>(s.x - grid_lo_.x);
  }

  struct Drain {
    std::size_t cell = 0;
    bool own = false;
  };

  HeightfieldPtr in_, rainfall_, sinks_;
  WaterFlowParams p_;
  Domain whole_domain_;
  glm::ivec2 whole_;
  SampleRect rect_;
  glm::ivec2 own_hi_;  // the samples the tile counts in sums: [rect_.lo, own_hi_)
  int block_ = 0, halo_ = 0;
  glm::ivec2 grid_lo_{0}, grid_size_{0};
  std::vector<float> z_, rain_grid_, sink_grid_;  // on the grid
  std::optional<WaterFlowGrid> grid_;
  std::optional<BandCells> cells_;  // of the grid
  std::vector<std::size_t> band_cells_, halo_cells_;
  std::vector<Drain> drains_;
  ExactDoubleSum rain_, border_, sink_;  // of the tile's own samples
  ExactDoubleSum total_;                 // moved over the whole domain so far
  std::vector<double> w_start_, flux_start_;
  ExactDoubleSum border_start_, sink_start_;  // at the start of the block
  int done_ = 0;                              // iterations run and kept
  bool finished_ = false;
  double rain_sum_ = 0.0, stored_sum_ = 0.0, border_sum_ = 0.0, sink_sum_ = 0.0;  // over the whole domain
};

class WaterFlowAcrossTiles : public TileGraphAlgorithm {
 public:
  WaterFlowAcrossTiles(const WaterFlowParams& p, const Domain& whole, int block)
      : params_(p), whole_domain_(whole), whole_(whole.resolution), fixed_block_(block) {}

  int rounds() const override { return 2; }

  // Round r >= 2 ran block r - 2; after the block the run stops at, one more round sums the report.
  bool another_round(int round, const std::vector<std::string>& messages) const override {
    if (round < 2) return true;
    const auto headers = take_headers(messages);
    return !headers[0].last;
  }

  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    const HeightfieldPtr in = tile_heightfield(inputs, 0), rainfall = tile_heightfield(inputs, 1),
                         sinks = tile_heightfield(inputs, 2);
    if (!in) throw std::invalid_argument("water flow across tiles needs a heightfield input");
    for (const auto& f : {rainfall, sinks})
      if (f && f->domain.resolution != in->domain.resolution)
        throw std::invalid_argument("water flow across tiles: rainfall and sinks must lie on the tile");
    require_finite_inputs("WaterFlow", {{"in", in.get()}, {"rainfall", rainfall.get()}, {"sinks", sinks.get()}});
    return std::make_unique<WaterTile>(in, rainfall, sinks, params_, whole_domain_);
  }

  // Round 0: the iterations per exchange. Round 1: each tile's static halo. A block round: the verdict over all tiles
  // (iterations kept, whether the run stops, the total moved after them) and, unless it stops, each tile's water
  // halo, sample by sample from the bands of the tile holding it nearest to this one. The last round: the report's
  // sums over all tiles.
  std::vector<std::string> solve(int round, const std::vector<std::string>& messages) const override {
    const std::size_t count = messages.size();
    const auto headers = take_headers(messages);
    const int k = block(headers);
    std::vector<std::string> answers(count);
    if (round == 0) {
      for (auto& a : answers) bytes::put(a, static_cast<std::int32_t>(k));
      return answers;
    }
    for (const Header& h : headers)
      if (h.width != kReach * k || h.last != headers[0].last || h.done != headers[0].done || h.ran != headers[0].ran ||
          h.channels != headers[0].channels || h.sums.size() != headers[0].sums.size())
        throw std::invalid_argument("water flow bands: the tiles' messages do not fit together");
    if (headers[0].last) {
      if (headers[0].sums.size() != 4) throw std::invalid_argument("water flow bands: the report's sums are missing");
      std::string a;
      for (std::size_t s = 0; s < 4; ++s) {
        ExactDoubleSum total;
        for (const Header& h : headers) total.add(h.sums[s]);
        bytes::put(a, total.value());
      }
      for (std::size_t t = 0; t < count; ++t)
        if (messages[t].size() != headers[t].bytes()) throw std::invalid_argument("water flow bands: truncated bytes");
      answers.assign(count, a);
      return answers;
    }
    std::string verdict;
    if (round >= 2) {
      const Verdict v = judge(headers);
      bytes::put(verdict, v.keep);
      bytes::put(verdict, static_cast<std::int32_t>(v.stop));
      v.total.put(verdict);
      if (v.stop) {
        answers.assign(count, verdict);
        return answers;
      }
    }
    answers.assign(count, verdict);
    erosion::append_halos(answers, headers, messages, plans_, whole_, kReach * k, "water flow bands");
    return answers;
  }

 private:
  std::vector<Header> take_headers(const std::vector<std::string>& messages) const {
    std::vector<Header> headers;
    for (const auto& m : messages) {
      headers.push_back(take_header(m));
      erosion::check_tile_rect(headers.back().rect, whole_, "water flow bands");
    }
    if (headers.empty()) throw std::invalid_argument("water flow bands: no tiles");
    return headers;
  }

  // The whole-domain run's stop test on the block's iterations, from the tiles' exact sums.
  Verdict judge(const std::vector<Header>& headers) const {
    const Header& first = headers[0];
    if (first.ran < 1 || first.sums.size() != static_cast<std::size_t>(first.ran) + 1)
      throw std::invalid_argument("water flow bands: a block without iterations");
    Verdict v;
    v.total = first.sums[0];
    const std::string total_bytes = sum_bytes(v.total);
    for (const Header& h : headers)
      if (sum_bytes(h.sums[0]) != total_bytes)
        throw std::invalid_argument("water flow bands: the tiles disagree on the water moved so far");
    for (std::int32_t i = 0; i < first.ran; ++i) {
      ExactDoubleSum moved_sum;
      for (const Header& h : headers) moved_sum.add(h.sums[static_cast<std::size_t>(i) + 1]);
      const double moved = moved_sum.value();
      if (!(moved > 0.0)) {  // nothing moved: the whole-domain run stops before this iteration
        v.keep = i, v.stop = true;
        return v;
      }
      v.total.add(moved_sum);
      if (water_flow_settled(moved, v.total.value(), params_.threshold)) {
        v.keep = i + 1, v.stop = true;
        return v;
      }
    }
    v.keep = first.ran;
    v.stop = first.done + first.ran >= params_.max_iterations;
    return v;
  }

  // Iterations per exchange: fixed, or from the smallest tile.
  int block(const std::vector<Header>& headers) const {
    return fixed_block_ > 0 ? fixed_block_ : erosion::iterations_per_exchange(headers, whole_);
  }

  WaterFlowParams params_;
  Domain whole_domain_;
  glm::ivec2 whole_;
  int fixed_block_;  // iterations per exchange, or 0: from the smallest tile
  mutable erosion::HaloPlanCache plans_;
};

WaterFlowParams params_of(const ParamView& v) {
  WaterFlowParams p;
  p.rainfall = v.get<double>("rainfall");
  p.infiltration = v.get<double>("infiltration");
  p.threshold = v.get<double>("threshold");
  p.max_iterations = static_cast<int>(v.get<std::int64_t>("max_iterations"));
  return p;
}

// Every parameter value and every linked input runs across the tiles; a run the whole-domain node would refuse (too
// much work) stays on the whole domain, whose node reports why (tile_graph_for).
const bool kWaterFlowRegistered = register_tile_graph(
    "WaterFlow", [](const ParamView& v, const Domain& whole) { return water_flow_across_tiles(params_of(v), whole); });

}  // namespace

std::unique_ptr<TileGraphAlgorithm> water_flow_across_tiles(const WaterFlowParams& p, const Domain& whole,
                                                            int iterations_per_exchange) {
  if (whole.resolution.x > 0 && whole.resolution.y > 0)
    check_work(static_cast<double>(p.max_iterations) * static_cast<double>(whole.resolution.x) *
                   static_cast<double>(whole.resolution.y),
               "WaterFlow (max_iterations x samples)", "lower max_iterations or use a coarser grid");
  return std::make_unique<WaterFlowAcrossTiles>(p, whole, iterations_per_exchange);
}

}  // namespace orogen::hydrology
