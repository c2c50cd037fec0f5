// ThermalErosion across the tiles of a tiled or distributed build, exact (graph/tile_graph.h): each tile iterates on
// its own samples with a halo of 2 samples taken every iteration from its neighbors' border bands.
//
// Round 0 exchanges the bands of the heights, the rates (strength x mask) and, with a hardness input, the talus
// tangents. Round r >= 1 runs iteration r on every tile (nodes/erosion/thermal_step.h, the whole-domain run's own
// kernel) and exchanges the new bands of the heights, with each tile's largest change and largest total movement.
// One iteration reads the heights within 2 samples, so with the neighbors' values in its halo a tile computes its
// samples bit for bit as the whole-domain run; every tile sees every message, so all stop after the same iteration
// (the largest change over all tiles <= tolerance, or the iteration count), and `flow` divides by the largest
// movement over all tiles: the whole domain's, since tiles agree on the samples they share.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <tuple>
#include <stdexcept>

#include "graph/node_type.h"
#include "graph/tile_bytes.h"
#include "graph/tile_graph.h"
#include "nodes/common/finite_inputs.h"
#include "nodes/erosion/thermal_step.h"

namespace orogen::erosion {
namespace {

constexpr int kHalo = 2;  // one iteration reads the heights within 2 samples

// A rectangle of samples of the whole domain, both ends included.
struct SampleRect {
  glm::ivec2 lo{0, 0}, hi{-1, -1};
  glm::ivec2 size() const { return hi - lo + 1; }
  bool operator==(const SampleRect& o) const { return lo == o.lo && hi == o.hi; }
  bool operator<(const SampleRect& o) const {
    return std::tie(lo.x, lo.y, hi.x, hi.y) < std::tie(o.lo.x, o.lo.y, o.hi.x, o.hi.y);
  }
};

// A tile's border bands: its samples 1 and 2 inside each border it shares with a neighbor (the border samples
// themselves both tiles hold). One channel lays out the top rows, the bottom rows, the left columns and the right
// columns, each present when a neighbor lies on that side; a tile of 2 samples along an axis has one row or column.
class Bands {
 public:
  Bands(const SampleRect& r, glm::ivec2 whole) : r_(r) {
    const glm::ivec2 s = r.size();
    top_ = r.lo.y > 0 ? std::min(kHalo, s.y - 1) : 0;
    bottom_ = r.hi.y < whole.y - 1 ? std::min(kHalo, s.y - 1) : 0;
    left_ = r.lo.x > 0 ? std::min(kHalo, s.x - 1) : 0;
    right_ = r.hi.x < whole.x - 1 ? std::min(kHalo, s.x - 1) : 0;
  }

  // Values per channel.
  std::size_t size() const {
    const glm::ivec2 s = r_.size();
    return static_cast<std::size_t>(top_ + bottom_) * s.x + static_cast<std::size_t>(left_ + right_) * s.y;
  }

  // fn(sample) for every band sample in layout order.
  template <class Fn>
  void for_each(Fn&& fn) const {
    for (int y = r_.lo.y + 1; y <= r_.lo.y + top_; ++y)
      for (int x = r_.lo.x; x <= r_.hi.x; ++x) fn(glm::ivec2(x, y));
    for (int y = r_.hi.y - bottom_; y < r_.hi.y; ++y)
      for (int x = r_.lo.x; x <= r_.hi.x; ++x) fn(glm::ivec2(x, y));
    for (int y = r_.lo.y; y <= r_.hi.y; ++y)
      for (int x = r_.lo.x + 1; x <= r_.lo.x + left_; ++x) fn(glm::ivec2(x, y));
    for (int y = r_.lo.y; y <= r_.hi.y; ++y)
      for (int x = r_.hi.x - right_; x < r_.hi.x; ++x) fn(glm::ivec2(x, y));
  }

  // Where sample `s` lies in a channel, or npos when no band holds it.
  std::size_t index(glm::ivec2 s) const {
    const auto sx = static_cast<std::size_t>(r_.size().x), sy = static_cast<std::size_t>(r_.size().y);
    const auto lx = static_cast<std::size_t>(s.x - r_.lo.x), ly = static_cast<std::size_t>(s.y - r_.lo.y);
    std::size_t at = 0;
    if (s.y >= r_.lo.y + 1 && s.y <= r_.lo.y + top_) return (ly - 1) * sx + lx;
    at += static_cast<std::size_t>(top_) * sx;
    if (s.y >= r_.hi.y - bottom_ && s.y < r_.hi.y)
      return at + static_cast<std::size_t>(s.y - (r_.hi.y - bottom_)) * sx + lx;
    at += static_cast<std::size_t>(bottom_) * sx;
    if (s.x >= r_.lo.x + 1 && s.x <= r_.lo.x + left_) return at + ly * left_ + (lx - 1);
    at += static_cast<std::size_t>(left_) * sy;
    if (s.x >= r_.hi.x - right_ && s.x < r_.hi.x)
      return at + ly * right_ + static_cast<std::size_t>(s.x - (r_.hi.x - right_));
    return npos;
  }
  static constexpr std::size_t npos = std::numeric_limits<std::size_t>::max();

 private:
  SampleRect r_;
  int top_ = 0, bottom_ = 0, left_ = 0, right_ = 0;
};

// fn(sample) for every sample of the domain within kHalo of tile `r` and outside it, row by row.
template <class Fn>
void for_each_halo(const SampleRect& r, glm::ivec2 whole, Fn&& fn) {
  const glm::ivec2 lo = glm::max(r.lo - kHalo, glm::ivec2(0)), hi = glm::min(r.hi + kHalo, whole - 1);
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x)
      if (x < r.lo.x || x > r.hi.x || y < r.lo.y || y > r.hi.y) fn(glm::ivec2(x, y));
}

// A message: the tile's rectangle, its channel count, its largest change of the iteration and largest movement so
// far, then each channel's bands.
struct Header {
  SampleRect rect;
  std::int32_t channels = 0;
  float change = 0.0f, most_moved = 0.0f;
};
constexpr std::size_t kHeaderBytes = 5 * sizeof(std::int32_t) + 2 * sizeof(float);

void put_header(std::string& out, const Header& h) {
  bytes::put(out, h.rect.lo.x), bytes::put(out, h.rect.lo.y), bytes::put(out, h.rect.hi.x);
  bytes::put(out, h.rect.hi.y), bytes::put(out, h.channels), bytes::put(out, h.change);
  bytes::put(out, h.most_moved);
}

Header take_header(std::string_view in) {
  const char* what = "thermal erosion bands";
  Header h;
  h.rect.lo.x = bytes::take<std::int32_t>(in, what), h.rect.lo.y = bytes::take<std::int32_t>(in, what);
  h.rect.hi.x = bytes::take<std::int32_t>(in, what), h.rect.hi.y = bytes::take<std::int32_t>(in, what);
  h.channels = bytes::take<std::int32_t>(in, what);
  h.change = bytes::take<float>(in, what), h.most_moved = bytes::take<float>(in, what);
  return h;
}

class ThermalTile : public TileGraphTile {
 public:
  ThermalTile(HeightfieldPtr in, const Heightfield* mask, const Heightfield* hardness, const ThermalParams& p,
              const ThermalStencil& stencil, glm::ivec2 whole_first, glm::ivec2 whole)
      : in_(std::move(in)),
        stencil_(stencil),
        whole_(whole),
        grids_(in_->width() + 2 * kHalo, in_->height() + 2 * kHalo, hardness != nullptr) {
    rect_.lo = in_->domain.first - whole_first;
    rect_.hi = rect_.lo + in_->domain.resolution - 1;
    for (int j = 0; j < in_->height(); ++j)
      for (int i = 0; i < in_->width(); ++i) {
        const std::size_t k = in_->index(i, j), q = grids_.at(i + kHalo, j + kHalo);
        grids_.z[q] = in_->data[k];
        grids_.rate[q] = thermal_rate(p, mask ? mask->data[k] : 1.0f);
        if (hardness) grids_.tan_cell[q] = thermal_tangent(p, hardness->data[k]);
      }
    heights_ = {kHalo, kHalo, kHalo + in_->width(), kHalo + in_->height()};
    // The ratios one cell around the tile too, except beyond the domain's border (walls).
    ratios_ = {heights_.x0 - (rect_.lo.x > 0), heights_.y0 - (rect_.lo.y > 0), heights_.x1 + (rect_.hi.x < whole.x - 1),
               heights_.y1 + (rect_.hi.y < whole.y - 1)};
  }

  std::string message(int round) override {
    Header h;
    h.rect = rect_;
    if (round > 0) {
      h.change = thermal_iteration(grids_, stencil_, heights_, ratios_);
      for (int y = heights_.y0; y < heights_.y1; ++y)
        for (int x = heights_.x0; x < heights_.x1; ++x)
          most_moved_ = std::max(most_moved_, grids_.moved[grids_.at(x, y)]);
    }
    h.most_moved = most_moved_;
    const auto channels = this->channels(round);
    h.channels = static_cast<std::int32_t>(channels.size());
    std::string out;
    put_header(out, h);
    const Bands bands(rect_, whole_);
    out.reserve(out.size() + channels.size() * bands.size() * sizeof(float));
    for (const std::vector<float>* c : channels) bands.for_each([&](glm::ivec2 s) { bytes::put(out, (*c)[cell(s)]); });
    return out;
  }

  void answer(int round, std::string_view in) override {
    const char* what = "thermal erosion halo";
    most_moved_everywhere_ = bytes::take<float>(in, what);
    for (std::vector<float>* c : channels(round))
      for_each_halo(rect_, whole_, [&](glm::ivec2 s) { (*c)[cell(s)] = bytes::take<float>(in, what); });
    if (!in.empty()) throw std::invalid_argument("thermal erosion halo: bytes left over");
  }

  std::vector<PortValue> outputs() override {
    ErosionMaps maps;
    maps.out = std::make_shared<Heightfield>(in_->domain);
    maps.flow = std::make_shared<Heightfield>(in_->domain);
    for (int j = 0; j < in_->height(); ++j)
      for (int i = 0; i < in_->width(); ++i) {
        const std::size_t q = grids_.at(i + kHalo, j + kHalo);
        maps.out->at(i, j) = grids_.z[q];
        maps.flow->at(i, j) = thermal_flow(grids_.moved[q], most_moved_everywhere_);
      }
    fill_change_maps(*in_, maps, nullptr);
    return {HeightfieldPtr(maps.out), HeightfieldPtr(maps.erosion), HeightfieldPtr(maps.deposition),
            HeightfieldPtr(maps.flow)};
  }

 private:
  // What travels in round `round`: first the heights, rates and tangents, then the heights.
  std::vector<std::vector<float>*> channels(int round) {
    std::vector<std::vector<float>*> c{&grids_.z};
    if (round == 0) {
      c.push_back(&grids_.rate);
      if (!grids_.tan_cell.empty()) c.push_back(&grids_.tan_cell);
    }
    return c;
  }
  std::size_t cell(glm::ivec2 s) const { return grids_.at(s.x - rect_.lo.x + kHalo, s.y - rect_.lo.y + kHalo); }

  HeightfieldPtr in_;
  ThermalStencil stencil_;
  glm::ivec2 whole_;
  SampleRect rect_;
  ThermalGrids grids_;
  GridWindow heights_, ratios_;
  float most_moved_ = 0.0f;             // the most any sample of the tile sent so far
  float most_moved_everywhere_ = 0.0f;  // the same over all tiles, from the last answer
};

class ThermalAcrossTiles : public TileGraphAlgorithm {
 public:
  ThermalAcrossTiles(const ThermalParams& p, const ThermalStencil& stencil, const Domain& whole)
      : params_(p), stencil_(stencil), whole_first_(whole.first), whole_(whole.resolution) {}

  int rounds() const override { return 1 + stencil_.iterations; }

  // Round r >= 1 ran iteration r; the run stops as the whole-domain run does.
  bool another_round(int round, const std::vector<std::string>& messages) const override {
    if (round + 1 >= rounds()) return false;
    if (round == 0) return true;
    float change = 0.0f;
    for (const auto& m : messages) change = std::max(change, take_header(m).change);
    return change > params_.tolerance;
  }

  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    auto field = [&](std::size_t k) -> HeightfieldPtr {
      const auto* h = k < inputs.size() ? std::get_if<HeightfieldPtr>(&inputs[k]) : nullptr;
      return h ? *h : nullptr;
    };
    const HeightfieldPtr in = field(0), mask = field(1), hardness = field(2);
    if (!in) throw std::invalid_argument("thermal erosion across tiles needs a heightfield input");
    for (const auto& f : {mask, hardness})
      if (f && f->domain.resolution != in->domain.resolution)
        throw std::invalid_argument("thermal erosion across tiles: mask and hardness must lie on the tile");
    require_finite_inputs("ThermalErosion", {{"in", in.get()}, {"mask", mask.get()}, {"hardness", hardness.get()}});
    return std::make_unique<ThermalTile>(in, mask.get(), hardness.get(), params_, stencil_, whole_first_, whole_);
  }

  // Each tile's halo, sample by sample from the bands of the tile holding it nearest to this one, with the most any
  // sample of the domain moved.
  std::vector<std::string> solve(int round, const std::vector<std::string>& messages) const override {
    (void)round;
    const std::size_t count = messages.size();
    std::vector<Header> headers(count);
    float most_moved = 0.0f;
    for (std::size_t t = 0; t < count; ++t) {
      headers[t] = take_header(messages[t]);
      const Header& h = headers[t];
      if (h.channels != headers[0].channels || h.channels < 1 || h.rect.lo.x < 0 || h.rect.lo.y < 0 ||
          h.rect.hi.x >= whole_.x || h.rect.hi.y >= whole_.y || h.rect.size().x < 2 || h.rect.size().y < 2)
        throw std::invalid_argument("thermal erosion bands: a tile's rectangle or channels do not fit");
      if (messages[t].size() !=
          kHeaderBytes + static_cast<std::size_t>(h.channels) * Bands(h.rect, whole_).size() * sizeof(float))
        throw std::invalid_argument("thermal erosion bands: truncated bytes");
      most_moved = std::max(most_moved, h.most_moved);
    }
    const auto halos = plan(headers);
    std::vector<std::string> answers(count);
    for (std::size_t u = 0; u < count; ++u) {
      std::string& out = answers[u];
      out.reserve(sizeof(float) * (1 + halos->sources[u].size() * static_cast<std::size_t>(headers[u].channels)));
      bytes::put(out, most_moved);
      for (std::int32_t c = 0; c < headers[u].channels; ++c)
        for (const auto& [v, at] : halos->sources[u])
          out.append(messages[v].data() + at + static_cast<std::size_t>(c) * halos->stride[v], sizeof(float));
    }
    return answers;
  }

 private:
  // Where the halo samples of each tile lie in the messages (the tile sending it, the byte offset of its value in the
  // first channel) and each message's channel stride in bytes: the same every round, so made once per tiling.
  struct HaloPlan {
    std::vector<SampleRect> rects;
    std::vector<std::size_t> stride;
    std::vector<std::vector<std::pair<std::size_t, std::size_t>>> sources;
  };

  std::shared_ptr<const HaloPlan> plan(const std::vector<Header>& headers) const {
    std::vector<SampleRect> rects;
    for (const Header& h : headers) rects.push_back(h.rect);
    const std::lock_guard<std::mutex> lock(mutex_);
    if (plan_ && plan_->rects == rects) return plan_;
    auto p = std::make_shared<HaloPlan>();
    const std::size_t count = rects.size();
    std::vector<Bands> bands;
    std::map<SampleRect, std::size_t> tile_at;
    std::vector<std::pair<int, int>> columns, rows;
    for (std::size_t t = 0; t < count; ++t) {
      bands.emplace_back(rects[t], whole_);
      p->stride.push_back(bands[t].size() * sizeof(float));
      tile_at[rects[t]] = t;
      columns.emplace_back(rects[t].lo.x, rects[t].hi.x);
      rows.emplace_back(rects[t].lo.y, rects[t].hi.y);
    }
    for (auto* axis : {&columns, &rows}) {
      std::sort(axis->begin(), axis->end());
      axis->erase(std::unique(axis->begin(), axis->end()), axis->end());
    }
    if (tile_at.size() != count || columns.size() * rows.size() != count)
      throw std::invalid_argument("thermal erosion bands: the tiles do not form a tiling");
    // The column (row) holding coordinate v nearest to the tile's own [lo, hi]: past a shared border sample, so v
    // lies 1 or 2 samples inside the border facing the tile, in that tile's bands.
    auto nearest = [](const std::vector<std::pair<int, int>>& axis, int lo, int hi, int v) {
      if (v >= lo && v <= hi) return std::make_pair(lo, hi);
      std::pair<int, int> best{0, -1};
      for (const auto& range : axis)
        if (v >= range.first && v <= range.second &&
            (best.second < best.first || (v > hi) == (range.first < best.first)))
          best = range;
      return best;
    };
    p->sources.resize(count);
    for (std::size_t u = 0; u < count; ++u) {
      const SampleRect& r = rects[u];
      for_each_halo(r, whole_, [&](glm::ivec2 s) {
        const auto cx = nearest(columns, r.lo.x, r.hi.x, s.x), cy = nearest(rows, r.lo.y, r.hi.y, s.y);
        const auto it = tile_at.find(SampleRect{{cx.first, cy.first}, {cx.second, cy.second}});
        const std::size_t v = it == tile_at.end() ? count : it->second;
        const std::size_t at = v < count ? bands[v].index(s) : Bands::npos;
        if (at == Bands::npos) throw std::invalid_argument("thermal erosion bands: a halo sample no tile sends");
        p->sources[u].emplace_back(v, kHeaderBytes + at * sizeof(float));
      });
    }
    p->rects = std::move(rects);
    plan_ = p;
    return plan_;
  }

  ThermalParams params_;
  ThermalStencil stencil_;
  glm::ivec2 whole_first_, whole_;
  mutable std::mutex mutex_;
  mutable std::shared_ptr<const HaloPlan> plan_;  // of the last tiling solved
};

// Every parameter value runs across the tiles; a run the whole-domain node would refuse (too many iterations) stays
// on the whole domain, whose node reports why.
const bool kThermalRegistered = register_tile_graph("ThermalErosion", [](const ParamView& v, const Domain& whole) {
  ThermalParams p;
  p.talus_angle = v.get<double>("talus_angle");
  p.strength = v.get<double>("strength");
  p.travel_distance = v.get<double>("travel_distance");
  p.tolerance = v.get<double>("tolerance");
  std::unique_ptr<TileGraphAlgorithm> algorithm;
  try {
    algorithm = std::make_unique<ThermalAcrossTiles>(p, thermal_stencil(p, whole.spacing, whole.resolution), whole);
  } catch (const NodeError&) {}
  return algorithm;
});

}  // namespace
}  // namespace orogen::erosion
