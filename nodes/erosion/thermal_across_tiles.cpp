// ThermalErosion across the tiles of a tiled or distributed build, exact (graph/tile_graph.h): each tile iterates on
// its own samples with a halo taken from its neighbors' border bands every k iterations.
//
// One iteration reads the heights within 2 samples, so k iterations need a halo of 2k: a tile runs iteration i of a
// block of k on itself grown by 2 (k - 1 - i) samples, and after the block its own samples are exact. Round 0 settles
// k (the same for every tile, from the smallest tile: the halo's repeated work stays small); round 1 exchanges the
// bands of the heights, the rates (strength x mask) and, with a hardness input, the talus tangents; round r >= 2
// runs block r - 2 on every tile (nodes/erosion/thermal_step.h, the whole-domain run's own kernel) and exchanges the
// new height bands, with each tile's largest change and largest total movement after each iteration of the block.
// Every tile sees every message, so all stop after the iteration the whole-domain run stops after (the first whose
// largest change over all tiles is <= tolerance, or the iteration count): a tile that ran past it goes back to the
// block's start and runs again to it. `flow` divides by the largest movement over all tiles at that iteration: the
// whole domain's, since tiles agree on the samples they share.
#include "nodes/erosion/thermal_across_tiles.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include "graph/node_type.h"
#include "graph/tile_bytes.h"
#include "graph/tile_graph.h"
#include "nodes/common/finite_inputs.h"
#include "nodes/erosion/thermal_step.h"
#include "nodes/erosion/tile_bands.h"

namespace orogen::erosion {
namespace {

constexpr int kReach = 2;  // one iteration reads the heights within 2 samples

// A message: the tile's rectangle, the width of its bands, its channel count, the iterations it ran this round with
// its largest change in each and its largest total movement after each, then each channel's bands.
struct Header {
  SampleRect rect;
  std::int32_t width = 0, channels = 0;
  std::vector<float> change, most_moved;  // per iteration run
  std::size_t bytes() const { return 7 * sizeof(std::int32_t) + 2 * change.size() * sizeof(float); }
};

void put_header(std::string& out, const Header& h) {
  bytes::put(out, h.rect);
  for (const std::int32_t v : {h.width, h.channels, static_cast<std::int32_t>(h.change.size())}) bytes::put(out, v);
  for (const float v : h.change) bytes::put(out, v);
  for (const float v : h.most_moved) bytes::put(out, v);
}

Header take_header(std::string_view in) {
  const char* what = "thermal erosion bands";
  Header h;
  h.rect = bytes::take<SampleRect>(in, what);
  h.width = bytes::take<std::int32_t>(in, what), h.channels = bytes::take<std::int32_t>(in, what);
  const auto ran = bytes::take<std::int32_t>(in, what);
  if (ran < 0 || static_cast<std::size_t>(ran) > in.size() / (2 * sizeof(float)))
    throw std::invalid_argument("thermal erosion bands: truncated bytes");
  for (std::int32_t i = 0; i < ran; ++i) h.change.push_back(bytes::take<float>(in, what));
  for (std::int32_t i = 0; i < ran; ++i) h.most_moved.push_back(bytes::take<float>(in, what));
  return h;
}

class ThermalTile : public TileGraphTile {
 public:
  ThermalTile(HeightfieldPtr in, HeightfieldPtr mask, HeightfieldPtr hardness, const ThermalParams& p,
              const ThermalStencil& stencil, const Domain& whole)
      : in_(std::move(in)),
        mask_(std::move(mask)),
        hardness_(std::move(hardness)),
        p_(p),
        stencil_(stencil),
        whole_(whole.resolution),
        rect_(rect_of(in_->domain, whole)) {}

  std::string message(int round) override {
    Header h;
    h.rect = rect_;
    h.width = halo_;
    if (round >= 2) {
      const int ran = std::min(block_, stencil_.iterations - (round - 2) * block_);
      for (int i = 0; i < ran; ++i) {
        h.change.push_back(thermal_iteration(*grids_, stencil_, window(ran - 1 - i), window(ran - 1 - i, 1)));
        h.most_moved.push_back(most_moved());
      }
    }
    std::string out;
    if (round == 0) {
      put_header(out, h);
      return out;
    }
    const auto channels = this->channels(round);
    h.channels = static_cast<std::int32_t>(channels.size());
    put_header(out, h);
    out.reserve(out.size() + channels.size() * cells_->bands.size() * sizeof(float));
    for (const std::vector<float>* c : channels) cells_->bands.append(out, c->data());
    return out;
  }

  void answer(int round, std::string_view in) override {
    const char* what = "thermal erosion halo";
    if (round == 0) {
      block_ = bytes::take<std::int32_t>(in, what);
      if (block_ < 1) throw std::invalid_argument("thermal erosion halo: no iterations per exchange");
      start_grids();
    } else {
      const auto keep = bytes::take<std::int32_t>(in, what);
      most_moved_everywhere_ = bytes::take<float>(in, what);
      if (round >= 2 && keep < std::min(block_, stencil_.iterations - (round - 2) * block_)) {
        // The run stopped inside the block: back to its start, and the kept iterations again.
        grids_->z = z_start_, grids_->moved = moved_start_;
        for (int i = 0; i < keep; ++i)
          thermal_iteration(*grids_, stencil_, window(keep - 1 - i), window(keep - 1 - i, 1));
        return;
      }
      for (std::vector<float>* c : channels(round)) cells_->halo.take(in, c->data(), what);
      if (block_ > 1) z_start_ = grids_->z, moved_start_ = grids_->moved;  // a block of 1 never goes back
    }
    if (!in.empty()) throw std::invalid_argument("thermal erosion halo: bytes left over");
  }

  std::vector<PortValue> outputs() override {
    ErosionMaps maps;
    maps.out = std::make_shared<Heightfield>(in_->domain);
    maps.flow = std::make_shared<Heightfield>(in_->domain);
    for (int j = 0; j < in_->height(); ++j)
      for (int i = 0; i < in_->width(); ++i) {
        const std::size_t q = grids_->at(i + halo_, j + halo_);
        maps.out->at(i, j) = grids_->z[q];
        maps.flow->at(i, j) = thermal_flow(grids_->moved[q], most_moved_everywhere_);
      }
    fill_change_maps(*in_, maps, nullptr);
    return {HeightfieldPtr(maps.out), HeightfieldPtr(maps.erosion), HeightfieldPtr(maps.deposition),
            HeightfieldPtr(maps.flow)};
  }

 private:
  // The grids with the halo of `block_` iterations around the tile's own samples.
  void start_grids() {
    halo_ = kReach * block_;
    grids_ = std::make_unique<ThermalGrids>(in_->width() + 2 * halo_, in_->height() + 2 * halo_, hardness_ != nullptr);
    for (int j = 0; j < in_->height(); ++j)
      for (int i = 0; i < in_->width(); ++i) {
        const std::size_t k = in_->index(i, j), q = grids_->at(i + halo_, j + halo_);
        grids_->z[q] = in_->data[k];
        grids_->rate[q] = thermal_rate(p_, mask_ ? mask_->data[k] : 1.0f);
        if (hardness_) grids_->tan_cell[q] = thermal_tangent(p_, hardness_->data[k]);
      }
    mask_.reset(), hardness_.reset();
    cells_.emplace(rect_, whole_, halo_,
                   [&](glm::ivec2 s) { return grids_->at(s.x - rect_.lo.x + halo_, s.y - rect_.lo.y + halo_); });
  }

  // The tile grown by kReach x `later` samples (the iterations after this one in the block) and by `more`, within
  // the domain, in grid cells.
  GridWindow window(int later, int more = 0) const {
    const int g = kReach * later + more;
    const glm::ivec2 lo = glm::max(rect_.lo - g, glm::ivec2(0)) - rect_.lo + halo_,
                     hi = glm::min(rect_.hi + g, whole_ - 1) - rect_.lo + halo_;
    return {lo.x, lo.y, hi.x + 1, hi.y + 1};
  }

  // The most any of the tile's own samples sent so far.
  float most_moved() const {
    float m = 0.0f;
    for (int j = 0; j < in_->height(); ++j) {
      const float* row = grids_->moved.data() + grids_->at(halo_, j + halo_);
      for (int i = 0; i < in_->width(); ++i) m = std::max(m, row[i]);
    }
    return m;
  }

  // What travels in round `round` (>= 1): first the heights, rates and tangents, then the heights.
  std::vector<std::vector<float>*> channels(int round) {
    std::vector<std::vector<float>*> c{&grids_->z};
    if (round == 1) {
      c.push_back(&grids_->rate);
      if (!grids_->tan_cell.empty()) c.push_back(&grids_->tan_cell);
    }
    return c;
  }

  HeightfieldPtr in_, mask_, hardness_;
  ThermalParams p_;
  ThermalStencil stencil_;
  glm::ivec2 whole_;
  SampleRect rect_;
  int block_ = 0, halo_ = 0;  // iterations per exchange, and the halo they need
  std::unique_ptr<ThermalGrids> grids_;
  std::optional<BandCells> cells_;            // of the grids
  std::vector<float> z_start_, moved_start_;  // at the start of the block
  float most_moved_everywhere_ = 0.0f;        // over all tiles, at the iteration the run is at
};

class ThermalAcrossTiles : public TileGraphAlgorithm {
 public:
  ThermalAcrossTiles(const ThermalParams& p, const ThermalStencil& stencil, const Domain& whole, int block)
      : params_(p), stencil_(stencil), whole_domain_(whole), whole_(whole.resolution), fixed_block_(block) {}

  int rounds() const override { return 2; }

  // Round r >= 2 ran block r - 2; the run stops after the iteration the whole-domain run stops after.
  bool another_round(int round, const std::vector<std::string>& messages) const override {
    if (round == 0) return true;
    if (round == 1) return stencil_.iterations > 0;
    const auto headers = take_headers(messages);
    const std::vector<float> change = largest_changes(headers);
    if (std::any_of(change.begin(), change.end(), [&](float c) { return c <= params_.tolerance; })) return false;
    return (round - 1) * block(headers) < stencil_.iterations;
  }

  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    const HeightfieldPtr in = tile_heightfield(inputs, 0), mask = tile_heightfield(inputs, 1),
                         hardness = tile_heightfield(inputs, 2);
    if (!in) throw std::invalid_argument("thermal erosion across tiles needs a heightfield input");
    for (const auto& f : {mask, hardness})
      if (f && f->domain.resolution != in->domain.resolution)
        throw std::invalid_argument("thermal erosion across tiles: mask and hardness must lie on the tile");
    require_finite_inputs("ThermalErosion", {{"in", in.get()}, {"mask", mask.get()}, {"hardness", hardness.get()}});
    return std::make_unique<ThermalTile>(in, mask, hardness, params_, stencil_, whole_domain_);
  }

  // Round 0: the iterations per exchange. Then each tile's halo, sample by sample from the bands of the tile holding
  // it nearest to this one, with the iterations of the block to keep and the most any sample moved by then.
  std::vector<std::string> solve(int round, const std::vector<std::string>& messages) const override {
    const std::size_t count = messages.size();
    const auto headers = take_headers(messages);
    const int k = block(headers);
    std::vector<std::string> answers(count);
    if (round == 0) {
      for (auto& a : answers) bytes::put(a, static_cast<std::int32_t>(k));
      return answers;
    }
    const std::vector<float> change = largest_changes(headers);
    std::int32_t keep = 0;
    while (keep < static_cast<std::int32_t>(change.size()) &&
           change[static_cast<std::size_t>(keep)] > params_.tolerance)
      ++keep;
    if (keep < static_cast<std::int32_t>(change.size())) ++keep;  // the iteration that settled the run counts
    float most_moved = 0.0f;
    for (const Header& h : headers) {
      if (h.width != kReach * k || h.channels < 1 || h.channels != headers[0].channels ||
          h.change.size() != change.size())
        throw std::invalid_argument("thermal erosion bands: the tiles' bands do not fit together");
      if (keep > 0) most_moved = std::max(most_moved, h.most_moved[static_cast<std::size_t>(keep - 1)]);
    }
    for (std::string& out : answers) {
      bytes::put(out, keep);
      bytes::put(out, most_moved);
    }
    append_halos(answers, headers, messages, plans_, whole_, kReach * k, "thermal erosion bands");
    return answers;
  }

 private:
  std::vector<Header> take_headers(const std::vector<std::string>& messages) const {
    std::vector<Header> headers;
    for (const auto& m : messages) {
      headers.push_back(take_header(m));
      check_tile_rect(headers.back().rect, whole_, "thermal erosion bands");
    }
    if (headers.empty()) throw std::invalid_argument("thermal erosion bands: no tiles");
    return headers;
  }

  // Iterations per exchange: fixed, or from the smallest tile.
  int block(const std::vector<Header>& headers) const {
    return fixed_block_ > 0 ? fixed_block_ : iterations_per_exchange(headers, whole_);
  }

  // The largest change over all tiles in each iteration of the block.
  static std::vector<float> largest_changes(const std::vector<Header>& headers) {
    std::vector<float> change(headers[0].change.size(), 0.0f);
    for (const Header& h : headers) {
      if (h.change.size() != change.size())
        throw std::invalid_argument("thermal erosion bands: tiles ran different iterations");
      for (std::size_t i = 0; i < change.size(); ++i) change[i] = std::max(change[i], h.change[i]);
    }
    return change;
  }

  ThermalParams params_;
  ThermalStencil stencil_;
  Domain whole_domain_;
  glm::ivec2 whole_;
  int fixed_block_;  // iterations per exchange, or 0: from the smallest tile
  mutable HaloPlanCache plans_;
};

ThermalParams params_of(const ParamView& v) {
  ThermalParams p;
  p.talus_angle = v.get<double>("talus_angle");
  p.strength = v.get<double>("strength");
  p.travel_distance = v.get<double>("travel_distance");
  p.tolerance = v.get<double>("tolerance");
  return p;
}

// Every parameter value runs across the tiles; a run the whole-domain node would refuse (too many iterations) stays
// on the whole domain, whose node reports why (tile_graph_for).
const bool kThermalRegistered = register_tile_graph("ThermalErosion", [](const ParamView& v, const Domain& whole) {
  return thermal_across_tiles(params_of(v), whole);
});

}  // namespace

std::unique_ptr<TileGraphAlgorithm> thermal_across_tiles(const ThermalParams& p, const Domain& whole,
                                                         int iterations_per_exchange) {
  return std::make_unique<ThermalAcrossTiles>(p, thermal_stencil(p, whole.spacing, whole.resolution), whole,
                                              iterations_per_exchange);
}

}  // namespace orogen::erosion
