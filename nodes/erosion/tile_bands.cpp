#include "nodes/erosion/tile_bands.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <stdexcept>

namespace orogen::erosion {

std::shared_ptr<const HaloPlan> make_halo_plan(std::vector<SampleRect> rects, glm::ivec2 whole, int width,
                                               const std::string& what) {
  auto p = std::make_shared<HaloPlan>();
  const std::size_t count = rects.size();
  std::vector<Bands> bands;
  std::map<SampleRect, std::size_t> tile_at;
  std::vector<std::pair<int, int>> columns, rows;
  for (std::size_t t = 0; t < count; ++t) {
    bands.emplace_back(rects[t], whole, width);
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
    throw std::invalid_argument(what + ": the tiles do not form a tiling");
  // The column (row) holding coordinate v nearest to the tile's own [lo, hi]: past a shared border sample, so v
  // lies 1 to `width` samples inside the border facing the tile, in that tile's bands.
  auto nearest = [](const std::vector<std::pair<int, int>>& axis, int lo, int hi, int v) {
    if (v >= lo && v <= hi) return std::make_pair(lo, hi);
    std::pair<int, int> best{0, -1};
    for (const auto& range : axis)
      if (v >= range.first && v <= range.second && (best.second < best.first || (v > hi) == (range.first < best.first)))
        best = range;
    return best;
  };
  p->sources.resize(count);
  p->halo_size.resize(count);
  for (std::size_t u = 0; u < count; ++u) {
    const SampleRect& r = rects[u];
    for_each_halo(r, whole, width, [&](glm::ivec2 s) {
      const auto cx = nearest(columns, r.lo.x, r.hi.x, s.x), cy = nearest(rows, r.lo.y, r.hi.y, s.y);
      const auto it = tile_at.find(SampleRect{{cx.first, cy.first}, {cx.second, cy.second}});
      const std::size_t v = it == tile_at.end() ? count : it->second;
      const std::size_t at = v < count ? bands[v].index(s) : Bands::npos;
      if (at == Bands::npos) throw std::invalid_argument(what + ": a halo sample no tile sends");
      std::vector<HaloRun>& runs = p->sources[u];
      if (!runs.empty() && runs.back().tile == v &&
          runs.back().at + runs.back().count * sizeof(float) == at * sizeof(float))
        ++runs.back().count;
      else
        runs.push_back({v, at * sizeof(float), 1});
      ++p->halo_size[u];
    });
  }
  p->rects = std::move(rects);
  p->width = width;
  return p;
}

void check_tile_rect(const SampleRect& r, glm::ivec2 whole, const std::string& what) {
  if (r.lo.x < 0 || r.lo.y < 0 || r.hi.x >= whole.x || r.hi.y >= whole.y || r.size().x < 2 || r.size().y < 2)
    throw std::invalid_argument(what + ": a tile's rectangle does not fit the domain");
}

std::shared_ptr<const HaloPlan> HaloPlanCache::get(std::vector<SampleRect> rects, glm::ivec2 whole, int width,
                                                   const std::string& what) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!last_ || last_->rects != rects || last_->width != width)
    last_ = make_halo_plan(std::move(rects), whole, width, what);
  return last_;
}

void append_halo(std::string& out, const HaloPlan& plan, std::size_t u, int channels,
                 const std::vector<const char*>& bands) {
  std::size_t to = out.size();
  out.resize(to + plan.halo_size[u] * static_cast<std::size_t>(channels) * sizeof(float));
  for (int c = 0; c < channels; ++c)
    for (const HaloRun& run : plan.sources[u]) {
      const std::size_t n = run.count * sizeof(float);
      std::memcpy(out.data() + to, bands[run.tile] + run.at + static_cast<std::size_t>(c) * plan.stride[run.tile], n);
      to += n;
    }
}

void CellRuns::push_back(std::size_t cell) {
  if (!runs_.empty() && runs_.back().first + runs_.back().count == cell)
    ++runs_.back().count;
  else
    runs_.push_back({cell, 1});
  ++size_;
}

void CellRuns::append(std::string& out, const float* field) const {
  std::size_t to = out.size();
  out.resize(to + size_ * sizeof(float));
  for (const Run& run : runs_) {
    std::memcpy(out.data() + to, field + run.first, run.count * sizeof(float));
    to += run.count * sizeof(float);
  }
}

void CellRuns::take(std::string_view& in, float* field, const char* what) const {
  if (in.size() < size_ * sizeof(float)) throw std::invalid_argument(std::string(what) + ": truncated bytes");
  for (const Run& run : runs_) {
    std::memcpy(field + run.first, in.data(), run.count * sizeof(float));
    in.remove_prefix(run.count * sizeof(float));
  }
}

}  // namespace orogen::erosion
