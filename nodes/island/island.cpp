#include "nodes/island/island.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <stdexcept>

#include "graph/exec_context.h"
#include "nodes/island/island_random.h"
#include "nodes/island/voronoi.h"
#include "nodes/noise/lattice_hash.h"
#include "nodes/noise/noise_reference.h"

namespace orogen::island {
namespace {

constexpr std::array<BiomeInfo, kBiomeCount> kBiomes{{
    {"snow", 0.5f, 0.7f, {1.0f, 1.0f, 1.0f}},
    {"tundra", 0.5f, 0.5f, {0xbb / 255.0f, 0xbb / 255.0f, 0xaa / 255.0f}},
    {"bare", 0.4f, 0.4f, {0x88 / 255.0f, 0x88 / 255.0f, 0x88 / 255.0f}},
    {"scorched", 0.7f, 0.3f, {0x55 / 255.0f, 0x55 / 255.0f, 0x55 / 255.0f}},
    {"taiga", 0.4f, 0.3f, {0x99 / 255.0f, 0xaa / 255.0f, 0x77 / 255.0f}},
    {"shrubland", 0.5f, 0.2f, {0x88 / 255.0f, 0x99 / 255.0f, 0x77 / 255.0f}},
    {"temperate_desert", 0.1f, 0.1f, {0xc9 / 255.0f, 0xd2 / 255.0f, 0x9b / 255.0f}},
    {"temperate_rain_forest", 0.3f, 0.2f, {0x44 / 255.0f, 0x88 / 255.0f, 0x55 / 255.0f}},
    {"deciduous_forest", 0.3f, 0.4f, {0x67 / 255.0f, 0x94 / 255.0f, 0x59 / 255.0f}},
    {"grassland", 0.4f, 0.5f, {0x88 / 255.0f, 0xaa / 255.0f, 0x55 / 255.0f}},
    {"tropical_rain_forest", 0.3f, 0.2f, {0x33 / 255.0f, 0x77 / 255.0f, 0x55 / 255.0f}},
    {"tropical_seasonal_forest", 0.3f, 0.2f, {0x55 / 255.0f, 0x99 / 255.0f, 0x44 / 255.0f}},
    {"subtropical_desert", 0.3f, 0.6f, {0xd2 / 255.0f, 0xb9 / 255.0f, 0x8b / 255.0f}},
    {"beach", 0.3f, 0.5f, {0xa0 / 255.0f, 0x90 / 255.0f, 0x77 / 255.0f}},
    {"lake", 0.2f, 0.2f, {0x33 / 255.0f, 0x66 / 255.0f, 0x99 / 255.0f}},
    {"ocean", 0.2f, 0.1f, {0x44 / 255.0f, 0x44 / 255.0f, 0x7a / 255.0f}},
}};

using Index = std::size_t;
inline Index ix(int k) { return static_cast<Index>(k); }

// Bridson's Poisson-disk sampling (Bridson 2007) with k = 30 candidates in the annulus [r, 2r]; every draw is
// a counter-based hash of (seed, draw number). The radius is chosen so about `n` points fill the rectangle
// (maximal Poisson-disk sets reach a density of about 0.7 / r^2).
}  // namespace

std::vector<glm::dvec2> poisson_sites(glm::dvec2 lo, glm::dvec2 size, int n, std::uint64_t seed, const ExecContext* ctx) {
  const double r = std::sqrt(0.7 * size.x * size.y / std::max(1, n));
  const double cell = r / std::sqrt(2.0);
  const int gw = std::max(1, static_cast<int>(std::ceil(size.x / cell)));
  const int gh = std::max(1, static_cast<int>(std::ceil(size.y / cell)));
  if (static_cast<double>(gw) * gh > 1e8) throw std::runtime_error("Poisson sites: too many cells for this map");
  std::vector<int> grid(static_cast<std::size_t>(gw) * static_cast<std::size_t>(gh), -1);
  std::vector<glm::dvec2> pts;
  std::vector<int> active;
  std::uint64_t draw = 0;
  auto next = [&] { return unit_hash(seed, 0x504f4953ull, draw++); };
  auto grid_of = [&](glm::dvec2 p) {
    return glm::ivec2(std::clamp(static_cast<int>((p.x - lo.x) / cell), 0, gw - 1),
                      std::clamp(static_cast<int>((p.y - lo.y) / cell), 0, gh - 1));
  };
  auto add = [&](glm::dvec2 p) {
    const glm::ivec2 g = grid_of(p);
    grid[static_cast<std::size_t>(g.y) * static_cast<std::size_t>(gw) + static_cast<std::size_t>(g.x)] = static_cast<int>(pts.size());
    active.push_back(static_cast<int>(pts.size()));
    pts.push_back(p);
  };
  add(lo + size * glm::dvec2(next(), next()));
  for (std::size_t iter = 1; !active.empty(); ++iter) {
    if (ctx && (iter & 1023) == 0) ctx->check_cancelled();
    const std::size_t a = std::min(active.size() - 1, static_cast<std::size_t>(next() * static_cast<double>(active.size())));
    const glm::dvec2 base = pts[static_cast<std::size_t>(active[a])];
    bool placed = false;
    for (int k = 0; k < 30 && !placed; ++k) {
      const double ang = 6.283185307179586 * next();
      const double rad = r * std::sqrt(1.0 + 3.0 * next());  // uniform by area in the annulus
      const glm::dvec2 p = base + rad * glm::dvec2(std::cos(ang), std::sin(ang));
      if (p.x <= lo.x || p.y <= lo.y || p.x >= lo.x + size.x || p.y >= lo.y + size.y) continue;
      const glm::ivec2 g = grid_of(p);
      bool ok = true;
      for (int y = std::max(0, g.y - 2); y <= std::min(gh - 1, g.y + 2) && ok; ++y)
        for (int x = std::max(0, g.x - 2); x <= std::min(gw - 1, g.x + 2) && ok; ++x) {
          const int q = grid[static_cast<std::size_t>(y) * static_cast<std::size_t>(gw) + static_cast<std::size_t>(x)];
          if (q >= 0) {
            const glm::dvec2 d = pts[static_cast<std::size_t>(q)] - p;
            ok = glm::dot(d, d) >= r * r;
          }
        }
      if (ok) {
        add(p);
        placed = true;
      }
    }
    if (!placed) {
      active[a] = active.back();
      active.pop_back();
    }
  }
  return pts;
}

namespace {

// Dijkstra over corners with a deterministic order (distance, then index).
struct QueueItem {
  double d;
  int q;
  bool operator>(const QueueItem& o) const { return d > o.d || (d == o.d && q > o.q); }
};
using MinQueue = std::priority_queue<QueueItem, std::vector<QueueItem>, std::greater<QueueItem>>;

}  // namespace

const BiomeInfo& biome_info(Biome b) { return kBiomes[static_cast<std::size_t>(b)]; }

Biome whittaker_biome(double e, double m) {
  if (e > 0.8) {
    if (m >= 0.5) return Biome::Snow;
    if (m >= 1.0 / 3.0) return Biome::Tundra;
    if (m >= 1.0 / 6.0) return Biome::Bare;
    return Biome::Scorched;
  }
  if (e > 0.6) {
    if (m >= 2.0 / 3.0) return Biome::Taiga;
    if (m >= 1.0 / 3.0) return Biome::Shrubland;
    return Biome::TemperateDesert;
  }
  if (e > 0.3) {
    if (m >= 5.0 / 6.0) return Biome::TemperateRainForest;
    if (m >= 0.5) return Biome::DeciduousForest;
    if (m >= 1.0 / 6.0) return Biome::Grassland;
    return Biome::TemperateDesert;
  }
  if (m >= 2.0 / 3.0) return Biome::TropicalRainForest;
  if (m >= 1.0 / 3.0) return Biome::TropicalSeasonalForest;
  if (m >= 1.0 / 6.0) return Biome::Grassland;
  return Biome::SubtropicalDesert;
}

std::vector<glm::dvec2> island_sites(const IslandParams& p) {
  if (!(p.size.x > 0.0 && p.size.y > 0.0)) throw std::runtime_error("island: the map size must be positive");
  if (p.cells < 1) throw std::runtime_error("island: at least one cell is needed");
  std::vector<glm::dvec2> pts;
  if (p.distribution == SiteDistribution::Poisson) {
    pts = poisson_sites(p.min_corner, p.size, p.cells, p.seed);
  } else {
    pts.resize(static_cast<std::size_t>(p.cells));
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const double u = unit_hash(p.seed, 0x554e4946ull, 2 * i), v = unit_hash(p.seed, 0x554e4946ull, 2 * i + 1);
      // Open interval: never on the border.
      pts[i] = p.min_corner + p.size * glm::dvec2(0.0005 + 0.999 * u, 0.0005 + 0.999 * v);
    }
  }
  // Numbered along a Hilbert curve: cells and corners near in the map are near in memory.
  hilbert_sort(pts);
  return pts;
}

namespace {

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

}  // namespace

double island_shape_noise(const IslandParams& p, double x, double y) { return ShapeNoise(p)(x, y); }

void classify_island(PolygonMap& map, const IslandParams& p, const Heightfield* mask, const ExecContext* ctx) {
  const std::size_t nc = map.cells.size(), nq = map.corners.size(), ne = map.edges.size();
  const glm::dvec2 lo = map.min_corner, size = map.max_corner - map.min_corner;

  // 3. Water per corner.
  std::vector<char> qwater(nq, 0);
  const ShapeNoise shape_noise(p);
  for (std::size_t q = 0; q < nq; ++q) {
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
  if (ctx) ctx->check_cancelled();

  // 4. Cells: water, ocean (flood fill from the border), lake.
  std::vector<char> water(nc, 0), ocean(nc, 0);
  for (std::size_t c = 0; c < nc; ++c) {
    const auto& cell = map.cells[c];
    int wet = 0;
    for (int q : cell.corners) wet += qwater[ix(q)];
    water[c] = cell.border || (!cell.corners.empty() && wet >= p.water_fraction * static_cast<double>(cell.corners.size()));
  }
  {
    std::vector<int> stack;
    for (std::size_t c = 0; c < nc; ++c)
      if (map.cells[c].border) {
        ocean[c] = 1;
        stack.push_back(static_cast<int>(c));
      }
    while (!stack.empty()) {
      const int c = stack.back();
      stack.pop_back();
      for (int d : map.cells[ix(c)].neighbours)
        if (water[ix(d)] && !ocean[ix(d)]) {
          ocean[ix(d)] = 1;
          stack.push_back(d);
        }
    }
  }
  std::vector<char> lake(nc, 0), coast_cell(nc, 0);
  for (std::size_t c = 0; c < nc; ++c) {
    lake[c] = water[c] && !ocean[c];
    if (!water[c])
      for (int d : map.cells[c].neighbours) coast_cell[c] = coast_cell[c] || ocean[ix(d)];
  }
  // Corners: ocean, coast, lake, land.
  std::vector<char> qocean(nq, 0), qcoast(nq, 0), qlake(nq, 0), qland(nq, 0);
  for (std::size_t q = 0; q < nq; ++q) {
    int n_ocean = 0, n_land = 0, n_lake = 0;
    for (int c : map.corners[q].cells) {
      n_ocean += ocean[ix(c)];
      n_land += !water[ix(c)];
      n_lake += lake[ix(c)];
    }
    const int n = static_cast<int>(map.corners[q].cells.size());
    qocean[q] = n_ocean == n;
    qcoast[q] = n_ocean > 0 && n_land > 0;
    qlake[q] = n_lake > 0 && n_ocean == 0;
    qland[q] = !qocean[q] && !qcoast[q];  // inland: land or lake
  }

  // 5. Elevation. Land: Dijkstra from the coast (step 1 between dry corners, 0.01 along lakes).
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(nq, inf);
  {
    MinQueue queue;
    for (std::size_t q = 0; q < nq; ++q)
      if (qcoast[q]) {
        dist[q] = 0.0;
        queue.push({0.0, static_cast<int>(q)});
      }
    while (!queue.empty()) {
      const auto [d, q] = queue.top();
      queue.pop();
      if (d > dist[ix(q)]) continue;
      for (int r : map.corners[ix(q)].adjacent) {
        if (!qland[ix(r)]) continue;
        const double step = (qlake[ix(q)] || qlake[ix(r)]) ? 0.01 : 1.01;
        if (d + step < dist[ix(r)]) {
          dist[ix(r)] = d + step;
          queue.push({d + step, r});
        }
      }
    }
  }
  // Ocean: breadth-first steps from the coast.
  std::vector<int> odist(nq, -1);
  int max_odist = 0;
  {
    std::vector<int> frontier;
    for (std::size_t q = 0; q < nq; ++q)
      if (qcoast[q]) {
        odist[q] = 0;
        frontier.push_back(static_cast<int>(q));
      }
    for (std::size_t head = 0; head < frontier.size(); ++head) {
      const int q = frontier[head];
      for (int r : map.corners[ix(q)].adjacent)
        if (qocean[ix(r)] && odist[ix(r)] < 0) {
          odist[ix(r)] = odist[ix(q)] + 1;
          max_odist = std::max(max_odist, odist[ix(r)]);
          frontier.push_back(r);
        }
    }
  }
  std::vector<float> elevation(nq, 0.0f);
  {
    std::vector<int> land;
    for (std::size_t q = 0; q < nq; ++q)
      if (qland[q]) land.push_back(static_cast<int>(q));
    std::sort(land.begin(), land.end(), [&](int a, int b) {
      const double da = std::isfinite(dist[ix(a)]) ? dist[ix(a)] : 0.0, db = std::isfinite(dist[ix(b)]) ? dist[ix(b)] : 0.0;
      return da < db || (da == db && a < b);
    });
    const double n = static_cast<double>(land.size());
    for (std::size_t r = 0; r < land.size(); ++r) {
      const double x = (static_cast<double>(r) + 1.0) / n;  // in (0, 1]
      const double y = 1.0 - std::pow(1.0 - x, 1.0 / p.lowland_bias);
      elevation[ix(land[r])] = static_cast<float>(p.max_elevation * y);
    }
    for (std::size_t q = 0; q < nq; ++q)
      if (qocean[q])
        elevation[q] = static_cast<float>(-p.ocean_depth * (odist[q] < 0 ? 1.0 : static_cast<double>(odist[q]) / std::max(1, max_odist)));
  }

  // Downstream: toward the coast; lakes route to their outlet (their corner nearest the coast) and are
  // flattened to its elevation.
  std::vector<int> downstream(nq, -1);
  for (std::size_t q = 0; q < nq; ++q) {
    if (!qland[q]) continue;
    int best = -1;
    for (int r : map.corners[q].adjacent)
      if (dist[ix(r)] < dist[q] && (best < 0 || dist[ix(r)] < dist[ix(best)] || (dist[ix(r)] == dist[ix(best)] && r < best)))
        best = r;
    downstream[q] = best;
  }
  {
    std::vector<int> lake_of(nq, -1);
    std::vector<int> members;
    int lakes = 0;
    for (std::size_t q0 = 0; q0 < nq; ++q0) {
      if (!qlake[q0] || lake_of[q0] >= 0 || !qland[q0]) continue;
      // Component of lake corners.
      members.clear();
      members.push_back(static_cast<int>(q0));
      lake_of[q0] = lakes;
      for (std::size_t h = 0; h < members.size(); ++h)
        for (int r : map.corners[ix(members[h])].adjacent)
          if (qlake[ix(r)] && qland[ix(r)] && lake_of[ix(r)] < 0) {
            lake_of[ix(r)] = lakes;
            members.push_back(r);
          }
      int outlet = members[0];
      for (int q : members)
        if (dist[ix(q)] < dist[ix(outlet)] || (dist[ix(q)] == dist[ix(outlet)] && q < outlet)) outlet = q;
      const float level = elevation[ix(outlet)];
      for (int q : members) elevation[ix(q)] = level;
      // Breadth-first tree toward the outlet.
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
  }
  if (ctx) ctx->check_cancelled();

  // 6. Rivers.
  std::vector<float> qriver(nq, 0.0f), eriver(ne, 0.0f);
  std::vector<int> down_edge(nq, -1);
  for (std::size_t q = 0; q < nq; ++q)
    if (downstream[q] >= 0)
      for (int e : map.corners[q].edges) {
        const auto& edge = map.edges[ix(e)];
        if (edge.corners[0] == downstream[q] || edge.corners[1] == downstream[q]) down_edge[q] = e;
      }
  if (nq > 0) {
    int placed = 0;
    for (std::uint64_t attempt = 0; placed < p.rivers && attempt < static_cast<std::uint64_t>(p.rivers) * 20; ++attempt) {
      const std::size_t q0 = std::min(nq - 1, static_cast<std::size_t>(unit_hash(p.seed, 0x52495645ull, attempt) * static_cast<double>(nq)));
      const double e = elevation[q0] / p.max_elevation;
      if (!qland[q0] || qlake[q0] || e < 0.3 || e > 0.9) continue;
      ++placed;
      for (int q = static_cast<int>(q0); q >= 0; q = downstream[ix(q)]) {
        qriver[ix(q)] += 1.0f;
        if (down_edge[ix(q)] >= 0) eriver[ix(down_edge[ix(q)])] += 1.0f;
      }
    }
  }

  // 7. Moisture: fresh water spreading by breadth-first search (max-propagation, decay per step).
  std::vector<double> raw(nq, 0.0);
  {
    std::priority_queue<std::pair<double, int>> queue;  // max first; ties: larger index first (deterministic)
    for (std::size_t q = 0; q < nq; ++q) {
      if (!qland[q]) continue;
      double s = 0.0;
      if (qriver[q] > 0.0f) s = std::min(3.0, 0.2 * qriver[q]);
      if (qlake[q]) s = std::max(s, 1.0);
      raw[q] = s;
      if (s > 0.0) queue.push({s, static_cast<int>(q)});
    }
    while (!queue.empty()) {
      const auto [m, q] = queue.top();
      queue.pop();
      if (m < raw[ix(q)]) continue;
      const double next = m * p.moisture_decay;
      for (int r : map.corners[ix(q)].adjacent)
        if (qland[ix(r)] && next > raw[ix(r)]) {
          raw[ix(r)] = next;
          queue.push({next, r});
        }
    }
  }
  std::vector<float> moisture(nq, 1.0f);
  {
    std::vector<double> sorted;
    for (std::size_t q = 0; q < nq; ++q)
      if (qland[q]) sorted.push_back(raw[q]);
    std::sort(sorted.begin(), sorted.end());
    const double denom = std::max<double>(1.0, static_cast<double>(sorted.size()) - 1.0);
    for (std::size_t q = 0; q < nq; ++q)
      if (qland[q]) {
        const auto below = std::lower_bound(sorted.begin(), sorted.end(), raw[q]) - sorted.begin();
        moisture[q] = static_cast<float>(static_cast<double>(below) / denom);
      }
  }

  // 8. Cells.
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
    if (ocean[c]) b = Biome::Ocean;
    else if (lake[c]) b = Biome::Lake;
    else if (coast_cell[c]) b = Biome::Beach;
    else b = whittaker_biome(en, cmoist[c]);
    cbiome[c] = static_cast<float>(static_cast<int>(b));
  }

  auto as_float = [](const std::vector<char>& v) { return std::vector<float>(v.begin(), v.end()); };
  map.cell_attributes["water"] = as_float(water);
  map.cell_attributes["ocean"] = as_float(ocean);
  map.cell_attributes["lake"] = as_float(lake);
  map.cell_attributes["coast"] = as_float(coast_cell);
  map.cell_attributes["elevation"] = celev;
  map.cell_attributes["moisture"] = cmoist;
  map.cell_attributes["temperature"] = ctemp;
  map.cell_attributes["biome"] = cbiome;
  std::vector<char> qwet(nq);
  for (std::size_t q = 0; q < nq; ++q) qwet[q] = qocean[q] || qlake[q];
  map.corner_attributes["water"] = as_float(qwet);
  map.corner_attributes["ocean"] = as_float(qocean);
  map.corner_attributes["lake"] = as_float(qlake);
  map.corner_attributes["coast"] = as_float(qcoast);
  map.corner_attributes["elevation"] = elevation;
  map.corner_attributes["moisture"] = moisture;
  map.corner_attributes["moisture_raw"] = std::vector<float>(raw.begin(), raw.end());
  map.corner_attributes["river"] = qriver;
  map.corner_attributes["downstream"] = std::vector<float>(downstream.begin(), downstream.end());
  std::vector<float> fdist(nq, 0.0f);
  for (std::size_t q = 0; q < nq; ++q)
    fdist[q] = qland[q] ? static_cast<float>(std::isfinite(dist[q]) ? dist[q] : 0.0) : (qocean[q] ? -static_cast<float>(odist[q]) : 0.0f);
  map.corner_attributes["distance"] = fdist;
  map.edge_attributes["river"] = eriver;
}

PolygonMap generate_island(const IslandParams& p, const Heightfield* mask, const ExecContext* ctx,
                           std::vector<double>* lloyd_energy) {
  const glm::dvec2 lo = p.min_corner, hi = p.min_corner + p.size;
  std::vector<glm::dvec2> sites = island_sites(p);
  if (ctx) ctx->progress(0.1);
  PolygonMap map = relaxed_voronoi_diagram(std::move(sites), lo, hi, p.relaxation, lloyd_energy, ctx);
  if (ctx) ctx->progress(0.8);
  classify_island(map, p, mask, ctx);
  return map;
}

}  // namespace orogen::island
