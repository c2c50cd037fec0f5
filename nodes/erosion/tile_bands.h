#pragma once
// The border bands and halos of the tiles of a halo-exchange node run across tiles (graph/tile_graph.h): each tile
// sends its samples 1 to `width` inside each border it shares with a neighbor, and every tile takes its `width`-sample
// halo sample by sample from the tile holding it nearest to it (a tile narrower than the halo takes it from the tiles
// beyond). Shared by ThermalErosion, PipeErosion, WaterFlow and SunIllumination across tiles (docs/distributed.md).
#include <algorithm>
#include <cstddef>
#include <limits>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <glm/common.hpp>
#include <glm/vec2.hpp>

#include "graph/sample_rect.h"

namespace orogen::erosion {

// A tile's border bands of width `width`: its samples 1 to `width` inside each border it shares with a neighbor (the
// border samples themselves both tiles hold). One channel lays out the top rows, the bottom rows, the left columns
// and the right columns, each present when a neighbor lies on that side, and no wider than the tile.
class Bands {
 public:
  Bands(const SampleRect& r, glm::ivec2 whole, int width) : r_(r) {
    const glm::ivec2 s = r.size();
    top_ = r.lo.y > 0 ? std::min(width, s.y - 1) : 0;
    bottom_ = r.hi.y < whole.y - 1 ? std::min(width, s.y - 1) : 0;
    left_ = r.lo.x > 0 ? std::min(width, s.x - 1) : 0;
    right_ = r.hi.x < whole.x - 1 ? std::min(width, s.x - 1) : 0;
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

// fn(sample) for every sample of the domain within `width` of tile `r` and outside it, row by row.
template <class Fn>
void for_each_halo(const SampleRect& r, glm::ivec2 whole, int width, Fn&& fn) {
  const glm::ivec2 lo = glm::max(r.lo - width, glm::ivec2(0)), hi = glm::min(r.hi + width, whole - 1);
  for (int y = lo.y; y <= hi.y; ++y) {
    const bool beside = y >= r.lo.y && y <= r.hi.y;  // a row of the tile: only the columns left and right of it
    for (int x = lo.x; x <= hi.x; ++x) {
      if (beside && x == r.lo.x) x = r.hi.x + 1;
      if (x <= hi.x) fn(glm::ivec2(x, y));
    }
  }
}

// Throws std::invalid_argument, its message starting with `what`, unless tile `r` lies in a `whole`-sample domain and
// is at least 2 x 2 samples (its bands lie inside its borders).
void check_tile_rect(const SampleRect& r, glm::ivec2 whole, const std::string& what);

// `count` values of one channel of a tile's bands, at byte `at` of that channel.
struct HaloRun {
  std::size_t tile = 0, at = 0, count = 0;
};

// Where the halo samples of each tile lie in the messages, as runs of values consecutive in both the halo and one
// tile's bands, and each message's channel stride in bytes: the same every round, so made once per tiling.
struct HaloPlan {
  std::vector<SampleRect> rects;
  int width = 0;
  std::vector<std::size_t> stride;
  std::vector<std::vector<HaloRun>> sources;
  std::vector<std::size_t> halo_size;  // values per channel of each tile's halo
};

// The plan of the tiles `rects` (row-major over the tiling) of a `whole`-sample domain for halos of `width` samples.
// Throws std::invalid_argument, its message starting with `what`, when the rectangles do not form a tiling.
std::shared_ptr<const HaloPlan> make_halo_plan(std::vector<SampleRect> rects, glm::ivec2 whole, int width,
                                               const std::string& what);

// The plan of the last tiling asked for, kept across the rounds of a run (solve is const and may run on several
// threads).
class HaloPlanCache {
 public:
  std::shared_ptr<const HaloPlan> get(std::vector<SampleRect> rects, glm::ivec2 whole, int width,
                                      const std::string& what);

 private:
  std::mutex mutex_;
  std::shared_ptr<const HaloPlan> last_;
};

// Appends the halo of tile `u` in `channels` channels, each from the bands of the tile holding it: `bands[v]` is
// where tile v's bands start in its message (each channel plan.stride[v] bytes).
void append_halo(std::string& out, const HaloPlan& plan, std::size_t u, int channels,
                 const std::vector<const char*>& bands);

// The iterative stencils that exchange a k-wide halo every k iterations (ThermalErosion, WaterFlow): one iteration per
// 64 samples of the smallest tile side, so the halo ring's repeated work stays within about 4 k / side ~ 6% of a
// tile's, and at most 8. `headers` are the tiles' message headers (each with its `rect`).
template <class Header>
int iterations_per_exchange(const std::vector<Header>& headers, glm::ivec2 whole) {
  glm::ivec2 smallest = whole;
  for (const Header& h : headers) smallest = glm::min(smallest, h.rect.size());
  return std::clamp(std::min(smallest.x, smallest.y) / 64, 1, 8);
}

// Appends to each answer u the halo of tile u, `width` samples wide, taken from the tiles' messages: message t is
// its header (`headers[t]`: `rect`, `bytes()`, `channels`) followed by `channels` channels of its bands. Throws
// std::invalid_argument, its message starting with `what`, when a message holds anything else.
template <class Header>
void append_halos(std::vector<std::string>& answers, const std::vector<Header>& headers,
                  const std::vector<std::string>& messages, HaloPlanCache& plans, glm::ivec2 whole, int width,
                  const std::string& what) {
  std::vector<SampleRect> rects;
  for (const Header& h : headers) rects.push_back(h.rect);
  const auto halos = plans.get(std::move(rects), whole, width, what);
  std::vector<const char*> bands(messages.size());
  for (std::size_t t = 0; t < messages.size(); ++t) {
    if (messages[t].size() != headers[t].bytes() + static_cast<std::size_t>(headers[t].channels) * halos->stride[t])
      throw std::invalid_argument(what + ": truncated bytes");
    bands[t] = messages[t].data() + headers[t].bytes();
  }
  for (std::size_t u = 0; u < answers.size(); ++u) append_halo(answers[u], *halos, u, headers[u].channels, bands);
}

// Cells of a grid in an order, kept as runs of consecutive cells so values move a run per memcpy.
class CellRuns {
 public:
  void push_back(std::size_t cell);
  std::size_t size() const { return size_; }  // cells
  // Appends the values of `field` at the cells, in order.
  void append(std::string& out, const float* field) const;
  // Writes the cells of `field` from the front of `in`, in order; throws std::invalid_argument naming `what` when
  // `in` is too short.
  void take(std::string_view& in, float* field, const char* what) const;

 private:
  struct Run {
    std::size_t first = 0, count = 0;
  };
  std::vector<Run> runs_;
  std::size_t size_ = 0;
};

// The grid cells of a tile's bands and of its halo, in sending order, made once per tile: `cell(sample)` is the grid
// cell of a sample of the whole domain.
struct BandCells {
  CellRuns bands, halo;
  template <class Cell>
  BandCells(const SampleRect& r, glm::ivec2 whole, int width, Cell&& cell) {
    Bands(r, whole, width).for_each([&](glm::ivec2 s) { bands.push_back(cell(s)); });
    for_each_halo(r, whole, width, [&](glm::ivec2 s) { halo.push_back(cell(s)); });
  }
};

}  // namespace orogen::erosion
