#include "nodes/hydrology/pit_basin_fill.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>

#include "nodes/hydrology/flow_routing.h"

namespace orogen::hydrology {

std::vector<std::pair<std::int64_t, float>> fill_pit_basins(std::vector<BasinSample> samples, glm::ivec2 domain) {
  const std::int64_t count = static_cast<std::int64_t>(domain.x) * domain.y;
  std::sort(samples.begin(), samples.end(),
            [](const BasinSample& a, const BasinSample& b) { return a.sample < b.sample; });
  // One node per sample.
  std::vector<BasinSample> node;
  for (const BasinSample& s : samples) {
    if (s.sample < 0 || s.sample >= count) throw std::invalid_argument("pit basin fill: a sample outside the domain");
    if (!node.empty() && node.back().sample == s.sample) {
      if (std::bit_cast<std::uint32_t>(node.back().z) != std::bit_cast<std::uint32_t>(s.z))
        throw std::invalid_argument("pit basin fill: copies of a sample disagree");
      node.back().inside = node.back().inside || s.inside;
    } else {
      node.push_back(s);
    }
  }
  const auto n = static_cast<std::int32_t>(node.size());
  auto find = [&](std::int64_t sample) {
    const auto it = std::lower_bound(node.begin(), node.end(), sample,
                                     [](const BasinSample& a, std::int64_t s) { return a.sample < s; });
    return it != node.end() && it->sample == sample ? static_cast<std::int32_t>(it - node.begin()) : -1;
  };
  // The 8 neighbours of every node that were given (all of them for a node inside).
  std::vector<std::int32_t> neighbour(static_cast<std::size_t>(n) * 8, -1);
  for (std::int32_t a = 0; a < n; ++a) {
    const int i = static_cast<int>(node[a].sample % domain.x), j = static_cast<int>(node[a].sample / domain.x);
    for (int k = 0; k < 8; ++k) {
      const int x = i + kDi[k], y = j + kDj[k];
      if (x < 0 || y < 0 || x >= domain.x || y >= domain.y) continue;
      const std::int32_t b = find(static_cast<std::int64_t>(y) * domain.x + x);
      if (b < 0 && node[a].inside) throw std::invalid_argument("pit basin fill: a neighbor of a pit basin is missing");
      neighbour[static_cast<std::size_t>(a) * 8 + static_cast<std::size_t>(k)] = b;
    }
  }
  using Entry = std::pair<float, std::int32_t>;
  using Queue = std::priority_queue<Entry, std::vector<Entry>, std::greater<>>;
  constexpr float kInf = std::numeric_limits<float>::infinity();
  // The flat level: a Priority-Flood into the basins from the cells around them.
  std::vector<float> level(static_cast<std::size_t>(n), kInf);
  Queue queue;
  for (std::int32_t a = 0; a < n; ++a)
    if (!node[a].inside) queue.push({level[a] = node[a].z, a});
  while (!queue.empty()) {
    const auto [l, a] = queue.top();
    queue.pop();
    for (int k = 0; k < 8; ++k) {
      const std::int32_t b = neighbour[static_cast<std::size_t>(a) * 8 + static_cast<std::size_t>(k)];
      if (b < 0 || !node[b].inside || level[b] != kInf) continue;
      queue.push({level[b] = std::max(node[b].z, l), b});
    }
  }
  // The epsilon surface: lowered from +inf in Dijkstra order from the cells around the basins (at their height).
  std::vector<float> e(static_cast<std::size_t>(n), kInf);
  for (std::int32_t a = 0; a < n; ++a)
    if (!node[a].inside) queue.push({e[a] = node[a].z, a});
  while (!queue.empty()) {
    const auto [v, a] = queue.top();
    queue.pop();
    if (v != e[a]) continue;  // lowered since
    const float up = std::nextafter(v, kInf);
    for (int k = 0; k < 8; ++k) {
      const std::int32_t b = neighbour[static_cast<std::size_t>(a) * 8 + static_cast<std::size_t>(k)];
      if (b < 0 || !node[b].inside) continue;
      const float w = std::max(level[b], up);
      if (w < e[b]) queue.push({e[b] = w, b});
    }
  }
  std::vector<std::pair<std::int64_t, float>> filled;
  for (std::int32_t a = 0; a < n; ++a)
    if (node[a].inside) filled.emplace_back(node[a].sample, e[a]);
  return filled;
}

}  // namespace orogen::hydrology
