#include "nodes/erosion/tile_bands.h"

#include <algorithm>
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
  for (std::size_t u = 0; u < count; ++u) {
    const SampleRect& r = rects[u];
    for_each_halo(r, whole, width, [&](glm::ivec2 s) {
      const auto cx = nearest(columns, r.lo.x, r.hi.x, s.x), cy = nearest(rows, r.lo.y, r.hi.y, s.y);
      const auto it = tile_at.find(SampleRect{{cx.first, cy.first}, {cx.second, cy.second}});
      const std::size_t v = it == tile_at.end() ? count : it->second;
      const std::size_t at = v < count ? bands[v].index(s) : Bands::npos;
      if (at == Bands::npos) throw std::invalid_argument(what + ": a halo sample no tile sends");
      p->sources[u].emplace_back(v, at * sizeof(float));
    });
  }
  p->rects = std::move(rects);
  p->width = width;
  return p;
}

}  // namespace orogen::erosion
