// Steps 3-8 of the Voronoi island (island.h): water, ocean, lakes and coast; elevation; rivers; moisture;
// the cells' averages and biomes. One function per step, in the order classify_island runs them.
#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

#include "graph/exec_context.h"
#include "nodes/island/cell_index.h"
#include "nodes/island/island.h"
#include "nodes/island/island_random.h"
#include "nodes/noise/lattice_hash.h"
#include "nodes/noise/noise_reference.h"

namespace orogen::island {
namespace {

// Dijkstra over corners with a deterministic order (distance, then index).
struct QueueItem {
  double d;
  int q;
  bool operator>(const QueueItem& o) const { return d > o.d || (d == o.d && q > o.q); }
};
using MinQueue = std::priority_queue<QueueItem, std::vector<QueueItem>, std::greater<QueueItem>>;

// The shape noise's per-octave keys and lattice shifts (hashed once, not per corner).
struct ShapeNoise {
  struct Octave {
    std::uint32_t key;
    double sx, sy, freq, amp;
  };
  std::vector<Octave> octaves;
  explicit ShapeNoise(const IslandParams& p) {
    double amp = 0.5, freq = p.shape_frequency;
    for (int i = 0; i < p.shape_octaves; ++i) {
      const auto o = static_cast<std::uint32_t>(i) + 100u;
      octaves.push_back({noise::stream_key(p.seed, noise::Stream::Perlin, o),
                         noise::stream_unit(p.seed, noise::Stream::OctaveOffset, o, 0) * 0.9 + 0.05,
                         noise::stream_unit(p.seed, noise::Stream::OctaveOffset, o, 1) * 0.9 + 0.05, freq, amp});
      amp *= p.shape_gain;
      freq *= 2.0;
    }
  }
  double operator()(double x, double y) const {
    double sum = 0.0;
    for (const auto& o : octaves) sum += o.amp * noise::reference::perlin(x * o.freq + o.sx, y * o.freq + o.sy, o.key);
    return sum;
  }
};

// Step 3: water per corner (1 water, 0 land).
std::vector<char> corner_water(const PolygonMap& map, const IslandParams& p, const Heightfield* mask) {
  const glm::dvec2 lo = map.min_corner, size = map.max_corner - map.min_corner;
  std::vector<char> qwater(map.corners.size(), 0);
  const ShapeNoise shape_noise(p);
  for (std::size_t q = 0; q < map.corners.size(); ++q) {
    const auto& corner = map.corners[q];
    if (corner.border) {
      qwater[q] = 1;
      continue;
    }
    if (mask) {
      const float v = mask->sample_world(corner.position.x, corner.position.y);
      qwater[q] = !(v >= 0.5f);
    } else {
      const glm::dvec2 n = 2.0 * (corner.position - lo) / size - 1.0;
      qwater[q] = shape_noise(n.x, n.y) < p.shape_offset + p.shape_scale * (n.x * n.x + n.y * n.y);
    }
  }
  return qwater;
}

// Step 4's classes, 0/1 per cell and per corner.
struct WaterClasses {
  std::vector<char> water, ocean, lake, coast;     // cells
  std::vector<char> qocean, qcoast, qlake, qland;  // corners; qland: inland (land or lake)
};

// Step 4: cells are water by their share of water corners; ocean is water flood-filled from the border,
// lakes the other water; corners take their classes from their cells.
WaterClasses classify_water(const PolygonMap& map, const std::vector<char>& qwater, double water_fraction) {
  const std::size_t nc = map.cells.size(), nq = map.corners.size();
  WaterClasses w;
  w.water.assign(nc, 0);
  w.ocean.assign(nc, 0);
  for (std::size_t c = 0; c < nc; ++c) {
    const auto& cell = map.cells[c];
    int wet = 0;
    for (int q : cell.corners) wet += qwater[ix(q)];
    w.water[c] =
        cell.border || (!cell.corners.empty() && wet >= water_fraction * static_cast<double>(cell.corners.size()));
  }
  std::vector<int> stack;
  for (std::size_t c = 0; c < nc; ++c)
    if (map.cells[c].border) {
      w.ocean[c] = 1;
      stack.push_back(static_cast<int>(c));
    }
  while (!stack.empty()) {
    const int c = stack.back();
    stack.pop_back();
    for (int d : map.cells[ix(c)].neighbours)
      if (w.water[ix(d)] && !w.ocean[ix(d)]) {
        w.ocean[ix(d)] = 1;
        stack.push_back(d);
      }
  }
  w.lake.assign(nc, 0);
  w.coast.assign(nc, 0);
  for (std::size_t c = 0; c < nc; ++c) {
    w.lake[c] = w.water[c] && !w.ocean[c];
    if (!w.water[c])
      for (int d : map.cells[c].neighbours) w.coast[c] = w.coast[c] || w.ocean[ix(d)];
  }
  w.qocean.assign(nq, 0);
  w.qcoast.assign(nq, 0);
  w.qlake.assign(nq, 0);
  w.qland.assign(nq, 0);
  for (std::size_t q = 0; q < nq; ++q) {
    int n_ocean = 0, n_land = 0, n_lake = 0;
    for (int c : map.corners[q].cells) {
      n_ocean += w.ocean[ix(c)];
      n_land += !w.water[ix(c)];
      n_lake += w.lake[ix(c)];
    }
    const int n = static_cast<int>(map.corners[q].cells.size());
    w.qocean[q] = n_ocean == n;
    w.qcoast[q] = n_ocean > 0 && n_land > 0;
    w.qlake[q] = n_lake > 0 && n_ocean == 0;
    w.qland[q] = !w.qocean[q] && !w.qcoast[q];
  }
  return w;
}

// Step 5, land: shortest-path distance from the coast over inland corners (1.01 per step between dry
// corners, 0.01 when either touches a lake); infinity where unreachable or not inland.
std::vector<double> coast_distance(const PolygonMap& map, const WaterClasses& w) {
  const std::size_t nq = map.corners.size();
  std::vector<double> dist(nq, std::numeric_limits<double>::infinity());
  MinQueue queue;
  for (std::size_t q = 0; q < nq; ++q)
    if (w.qcoast[q]) {
      dist[q] = 0.0;
      queue.push({0.0, static_cast<int>(q)});
    }
  while (!queue.empty()) {
    const auto [d, q] = queue.top();
    queue.pop();
    if (d > dist[ix(q)]) continue;
    for (int r : map.corners[ix(q)].adjacent) {
      if (!w.qland[ix(r)]) continue;
      const double step = (w.qlake[ix(q)] || w.qlake[ix(r)]) ? 0.01 : 1.01;
      if (d + step < dist[ix(r)]) {
        dist[ix(r)] = d + step;
        queue.push({d + step, r});
      }
    }
  }
  return dist;
}

// Step 5, ocean: breadth-first steps from the coast over ocean corners (-1 where unreached).
std::vector<int> ocean_steps(const PolygonMap& map, const WaterClasses& w, int& max_steps) {
  std::vector<int> odist(map.corners.size(), -1);
  max_steps = 0;
  std::vector<int> frontier;
  for (std::size_t q = 0; q < map.corners.size(); ++q)
    if (w.qcoast[q]) {
      odist[q] = 0;
      frontier.push_back(static_cast<int>(q));
    }
  for (std::size_t head = 0; head < frontier.size(); ++head) {
    const int q = frontier[head];
    for (int r : map.corners[ix(q)].adjacent)
      if (w.qocean[ix(r)] && odist[ix(r)] < 0) {
        odist[ix(r)] = odist[ix(q)] + 1;
        max_steps = std::max(max_steps, odist[ix(r)]);
        frontier.push_back(r);
      }
  }
  return odist;
}

// Step 5, heights: inland corners ranked by coast distance and redistributed to F(y) = 1 - (1 - y)^bias
// times max_elevation; the ocean falls linearly to -ocean_depth at the farthest step; the coast is 0.
std::vector<float> corner_elevation(const WaterClasses& w, const std::vector<double>& dist,
                                    const std::vector<int>& odist, int max_odist, const IslandParams& p) {
  const std::size_t nq = dist.size();
  std::vector<float> elevation(nq, 0.0f);
  std::vector<int> land;
  for (std::size_t q = 0; q < nq; ++q)
    if (w.qland[q]) land.push_back(static_cast<int>(q));
  std::sort(land.begin(), land.end(), [&](int a, int b) {
    const double da = std::isfinite(dist[ix(a)]) ? dist[ix(a)] : 0.0,
                 db = std::isfinite(dist[ix(b)]) ? dist[ix(b)] : 0.0;
    return da < db || (da == db && a < b);
  });
  const double n = static_cast<double>(land.size());
  for (std::size_t r = 0; r < land.size(); ++r) {
    const double x = (static_cast<double>(r) + 1.0) / n;  // in (0, 1]
    const double y = 1.0 - std::pow(1.0 - x, 1.0 / p.lowland_bias);
    elevation[ix(land[r])] = static_cast<float>(p.max_elevation * y);
  }
  for (std::size_t q = 0; q < nq; ++q)
    if (w.qocean[q])
      elevation[q] = static_cast<float>(-p.ocean_depth *
                                        (odist[q] < 0 ? 1.0 : static_cast<double>(odist[q]) / std::max(1, max_odist)));
  return elevation;
}

// Step 5, downstream: each inland corner's neighbor nearest the coast (ties: lower index), -1 if none is
// nearer. Every lake (a component of lake corners) then drains through its outlet, its corner nearest the
// coast: it is flattened to the outlet's elevation and its corners route along a breadth-first tree to it.
std::vector<int> downstream_corners(const PolygonMap& map, const WaterClasses& w, const std::vector<double>& dist,
                                    std::vector<float>& elevation) {
  const std::size_t nq = map.corners.size();
  std::vector<int> downstream(nq, -1);
  for (std::size_t q = 0; q < nq; ++q) {
    if (!w.qland[q]) continue;
    int best = -1;
    for (int r : map.corners[q].adjacent)
      if (dist[ix(r)] < dist[q] &&
          (best < 0 || dist[ix(r)] < dist[ix(best)] || (dist[ix(r)] == dist[ix(best)] && r < best)))
        best = r;
    downstream[q] = best;
  }
  std::vector<int> lake_of(nq, -1);
  std::vector<int> members;
  int lakes = 0;
  for (std::size_t q0 = 0; q0 < nq; ++q0) {
    if (!w.qlake[q0] || lake_of[q0] >= 0 || !w.qland[q0]) continue;
    members.clear();
    members.push_back(static_cast<int>(q0));
    lake_of[q0] = lakes;
    for (std::size_t h = 0; h < members.size(); ++h)
      for (int r : map.corners[ix(members[h])].adjacent)
        if (w.qlake[ix(r)] && w.qland[ix(r)] && lake_of[ix(r)] < 0) {
          lake_of[ix(r)] = lakes;
          members.push_back(r);
        }
    int outlet = members[0];
    for (int q : members)
      if (dist[ix(q)] < dist[ix(outlet)] || (dist[ix(q)] == dist[ix(outlet)] && q < outlet)) outlet = q;
    const float level = elevation[ix(outlet)];
    for (int q : members) elevation[ix(q)] = level;
    std::vector<int> order{outlet};
    lake_of[ix(outlet)] = -2 - lakes;
    for (std::size_t h = 0; h < order.size(); ++h)
      for (int r : map.corners[ix(order[h])].adjacent)
        if (lake_of[ix(r)] == lakes) {
          lake_of[ix(r)] = -2 - lakes;
          downstream[ix(r)] = order[h];
          order.push_back(r);
        }
    ++lakes;
  }
  return downstream;
}

struct RiverVolumes {
  std::vector<float> corner, edge;  // paths through each corner and edge
};

// Step 6: `rivers` sources at hashed inland corners (not lakes) of normalized height in [0.3, 0.9] (at most
// 20 draws per river), each adding one unit to every corner and edge down its downstream path.
RiverVolumes trace_rivers(const PolygonMap& map, const WaterClasses& w, const std::vector<float>& elevation,
                          const std::vector<int>& downstream, const IslandParams& p) {
  const std::size_t nq = map.corners.size();
  RiverVolumes v{std::vector<float>(nq, 0.0f), std::vector<float>(map.edges.size(), 0.0f)};
  std::vector<int> down_edge(nq, -1);
  for (std::size_t q = 0; q < nq; ++q)
    if (downstream[q] >= 0)
      for (int e : map.corners[q].edges) {
        const auto& edge = map.edges[ix(e)];
        if (edge.corners[0] == downstream[q] || edge.corners[1] == downstream[q]) down_edge[q] = e;
      }
  if (nq == 0) return v;
  int placed = 0;
  for (std::uint64_t attempt = 0; placed < p.rivers && attempt < static_cast<std::uint64_t>(p.rivers) * 20; ++attempt) {
    const std::size_t q0 =
        std::min(nq - 1, static_cast<std::size_t>(unit_hash(p.seed, 0x52495645ull, attempt) * static_cast<double>(nq)));
    const double e = elevation[q0] / p.max_elevation;
    if (!w.qland[q0] || w.qlake[q0] || e < 0.3 || e > 0.9) continue;
    ++placed;
    for (int q = static_cast<int>(q0); q >= 0; q = downstream[ix(q)]) {
      v.corner[ix(q)] += 1.0f;
      if (down_edge[ix(q)] >= 0) v.edge[ix(down_edge[ix(q)])] += 1.0f;
    }
  }
  return v;
}

// Step 7, spreading: fresh water (rivers min(3, 0.2 volume), lakes 1) propagated over inland corners by
// max-propagation, `decay` per step.
std::vector<double> raw_moisture(const PolygonMap& map, const WaterClasses& w, const std::vector<float>& qriver,
                                 double decay) {
  const std::size_t nq = map.corners.size();
  std::vector<double> raw(nq, 0.0);
  std::priority_queue<std::pair<double, int>> queue;  // max first; ties: larger index first (deterministic)
  for (std::size_t q = 0; q < nq; ++q) {
    if (!w.qland[q]) continue;
    double s = 0.0;
    if (qriver[q] > 0.0f) s = std::min(3.0, 0.2 * qriver[q]);
    if (w.qlake[q]) s = std::max(s, 1.0);
    raw[q] = s;
    if (s > 0.0) queue.push({s, static_cast<int>(q)});
  }
  while (!queue.empty()) {
    const auto [m, q] = queue.top();
    queue.pop();
    if (m < raw[ix(q)]) continue;
    const double next = m * decay;
    for (int r : map.corners[ix(q)].adjacent)
      if (w.qland[ix(r)] && next > raw[ix(r)]) {
        raw[ix(r)] = next;
        queue.push({next, r});
      }
  }
  return raw;
}

// Step 7, redistribution: an inland corner's moisture is the rank of its raw value among inland corners, in
// [0, 1]; ocean and coast corners are 1.
std::vector<float> moisture_ranks(const WaterClasses& w, const std::vector<double>& raw) {
  const std::size_t nq = raw.size();
  std::vector<float> moisture(nq, 1.0f);
  std::vector<double> sorted;
  for (std::size_t q = 0; q < nq; ++q)
    if (w.qland[q]) sorted.push_back(raw[q]);
  std::sort(sorted.begin(), sorted.end());
  const double denom = std::max<double>(1.0, static_cast<double>(sorted.size()) - 1.0);
  for (std::size_t q = 0; q < nq; ++q)
    if (w.qland[q]) {
      const auto below = std::lower_bound(sorted.begin(), sorted.end(), raw[q]) - sorted.begin();
      moisture[q] = static_cast<float>(static_cast<double>(below) / denom);
    }
  return moisture;
}

// Step 8: each cell's mean corner elevation and moisture, temperature 1 - normalized elevation, and biome
// (ocean, lake, beach on the coast, else Whittaker), written as cell attributes.
void write_cell_attributes(PolygonMap& map, const WaterClasses& w, const std::vector<float>& elevation,
                           const std::vector<float>& moisture, const IslandParams& p) {
  const std::size_t nc = map.cells.size();
  std::vector<float> celev(nc, 0.0f), cmoist(nc, 0.0f), ctemp(nc, 0.0f), cbiome(nc, 0.0f);
  for (std::size_t c = 0; c < nc; ++c) {
    const auto& cell = map.cells[c];
    double e = 0.0, m = 0.0;
    for (int q : cell.corners) {
      e += elevation[ix(q)];
      m += moisture[ix(q)];
    }
    const double k = std::max<std::size_t>(1, cell.corners.size());
    celev[c] = static_cast<float>(e / k);
    cmoist[c] = static_cast<float>(m / k);
    const double en = std::clamp(celev[c] / p.max_elevation, 0.0, 1.0);
    ctemp[c] = static_cast<float>(1.0 - en);
    Biome b;
    if (w.ocean[c])
      b = Biome::Ocean;
    else if (w.lake[c])
      b = Biome::Lake;
    else if (w.coast[c])
      b = Biome::Beach;
    else
      b = whittaker_biome(en, cmoist[c]);
    cbiome[c] = static_cast<float>(static_cast<int>(b));
  }
  const auto as_float = [](const std::vector<char>& v) { return std::vector<float>(v.begin(), v.end()); };
  map.cell_attributes["water"] = as_float(w.water);
  map.cell_attributes["ocean"] = as_float(w.ocean);
  map.cell_attributes["lake"] = as_float(w.lake);
  map.cell_attributes["coast"] = as_float(w.coast);
  map.cell_attributes["elevation"] = celev;
  map.cell_attributes["moisture"] = cmoist;
  map.cell_attributes["temperature"] = ctemp;
  map.cell_attributes["biome"] = cbiome;
}

}  // namespace

double island_shape_noise(const IslandParams& p, double x, double y) { return ShapeNoise(p)(x, y); }

void classify_island(PolygonMap& map, const IslandParams& p, const Heightfield* mask, const ExecContext* ctx) {
  const std::size_t nq = map.corners.size();
  const WaterClasses w = classify_water(map, corner_water(map, p, mask), p.water_fraction);
  if (ctx) ctx->check_cancelled();
  // Cancellation between the stages (each is a pass or a sort over the corners: tens of milliseconds at the
  // largest maps).
  const auto poll = [&] {
    if (ctx) ctx->check_cancelled();
  };
  const std::vector<double> dist = coast_distance(map, w);
  poll();
  int max_odist = 0;
  const std::vector<int> odist = ocean_steps(map, w, max_odist);
  poll();
  std::vector<float> elevation = corner_elevation(w, dist, odist, max_odist, p);
  poll();
  const std::vector<int> downstream = downstream_corners(map, w, dist, elevation);
  poll();
  RiverVolumes rivers = trace_rivers(map, w, elevation, downstream, p);
  poll();
  const std::vector<double> raw = raw_moisture(map, w, rivers.corner, p.moisture_decay);
  poll();
  const std::vector<float> moisture = moisture_ranks(w, raw);
  poll();
  write_cell_attributes(map, w, elevation, moisture, p);

  const auto as_float = [](const std::vector<char>& v) { return std::vector<float>(v.begin(), v.end()); };
  std::vector<char> qwet(nq);
  for (std::size_t q = 0; q < nq; ++q) qwet[q] = w.qocean[q] || w.qlake[q];
  map.corner_attributes["water"] = as_float(qwet);
  map.corner_attributes["ocean"] = as_float(w.qocean);
  map.corner_attributes["lake"] = as_float(w.qlake);
  map.corner_attributes["coast"] = as_float(w.qcoast);
  map.corner_attributes["elevation"] = elevation;
  map.corner_attributes["moisture"] = moisture;
  map.corner_attributes["moisture_raw"] = std::vector<float>(raw.begin(), raw.end());
  map.corner_attributes["river"] = std::move(rivers.corner);
  map.corner_attributes["downstream"] = std::vector<float>(downstream.begin(), downstream.end());
  std::vector<float> fdist(nq, 0.0f);
  for (std::size_t q = 0; q < nq; ++q)
    fdist[q] = w.qland[q] ? static_cast<float>(std::isfinite(dist[q]) ? dist[q] : 0.0)
                          : (w.qocean[q] ? -static_cast<float>(odist[q]) : 0.0f);
  map.corner_attributes["distance"] = fdist;
  map.edge_attributes["river"] = std::move(rivers.edge);
}

}  // namespace orogen::island
