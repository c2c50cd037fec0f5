#include "nodes/island/river_curves.h"

#include <cmath>

namespace orogen::island {

Curves river_curves(const PolygonMap& map, double river_width) {
  Curves out;
  const std::size_t nq = map.corners.size();
  const auto find = [&](const char* name) -> const std::vector<float>* {
    const auto it = map.corner_attributes.find(name);
    return it != map.corner_attributes.end() && it->second.size() == nq ? &it->second : nullptr;
  };
  const auto* river = find("river");
  const auto* down = find("downstream");
  const auto* elev = find("elevation");
  if (!river || !down) return out;
  auto next = [&](std::size_t q) {
    const int d = static_cast<int>((*down)[q]);
    return d >= 0 && d < static_cast<int>(nq) && (*river)[q] > 0.0f ? d : -1;
  };
  std::vector<int> upstream(nq, 0);
  for (std::size_t q = 0; q < nq; ++q)
    if (const int d = next(q); d >= 0) ++upstream[static_cast<std::size_t>(d)];
  // Starts: sources (no upstream river) and confluences (two or more) that flow on.
  std::vector<int> curve_at(nq, -1);
  std::vector<std::size_t> starts;
  for (std::size_t q = 0; q < nq; ++q)
    if ((*river)[q] > 0.0f && upstream[q] != 1 && next(q) >= 0) {
      curve_at[q] = static_cast<int>(starts.size());
      starts.push_back(q);
    }
  out.curves.resize(starts.size());
  std::vector<int> end_of(starts.size(), -1);
  for (std::size_t k = 0; k < starts.size(); ++k) {
    Curve& c = out.curves[k];
    auto push = [&](std::size_t q, float volume) {
      const glm::dvec2 p = map.corners[q].position;
      c.points.push_back({static_cast<float>(p.x), static_cast<float>(p.y), elev ? (*elev)[q] : 0.0f});
      c.width.push_back(static_cast<float>(river_width * std::sqrt(static_cast<double>(volume))));
      c.attributes["volume"].push_back(volume);
    };
    std::size_t q = starts[k];
    push(q, (*river)[q]);
    for (;;) {
      const int d = next(q);
      if (d < 0) break;
      // The last point carries the volume of the segment arriving there.
      const auto dq = static_cast<std::size_t>(d);
      const bool stop = upstream[dq] != 1 || next(dq) < 0;
      push(dq, stop ? (*river)[q] : (*river)[dq]);
      q = dq;
      if (stop) break;
    }
    end_of[k] = static_cast<int>(q);
  }
  for (std::size_t k = 0; k < starts.size(); ++k) out.curves[k].parent = curve_at[static_cast<std::size_t>(end_of[k])];
  return out;
}

}  // namespace orogen::island
