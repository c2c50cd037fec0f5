#include "nodes/island/island.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "graph/exec_context.h"
#include "nodes/island/island_random.h"
#include "nodes/island/voronoi.h"

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

}  // namespace

// Bridson's Poisson-disk sampling (Bridson 2007) with k = 30 candidates in the annulus [r, 2r]; every draw is
// a counter-based hash of (seed, draw number). The radius is chosen so about `n` points fill the rectangle
// (maximal Poisson-disk sets reach a density of about 0.7 / r^2).
std::vector<glm::dvec2> poisson_sites(glm::dvec2 lo, glm::dvec2 size, int n, std::uint64_t seed,
                                      const ExecContext* ctx) {
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
    grid[static_cast<std::size_t>(g.y) * static_cast<std::size_t>(gw) + static_cast<std::size_t>(g.x)] =
        static_cast<int>(pts.size());
    active.push_back(static_cast<int>(pts.size()));
    pts.push_back(p);
  };
  add(lo + size * glm::dvec2(next(), next()));
  for (std::size_t iter = 1; !active.empty(); ++iter) {
    if (ctx && (iter & 1023) == 0) ctx->check_cancelled();
    const std::size_t a =
        std::min(active.size() - 1, static_cast<std::size_t>(next() * static_cast<double>(active.size())));
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

std::vector<glm::dvec2> island_sites(const IslandParams& p, const ExecContext* ctx) {
  if (!(p.size.x > 0.0 && p.size.y > 0.0)) throw std::runtime_error("island: the map size must be positive");
  if (p.cells < 1) throw std::runtime_error("island: at least one cell is needed");
  std::vector<glm::dvec2> pts;
  if (p.distribution == SiteDistribution::Poisson) {
    pts = poisson_sites(p.min_corner, p.size, p.cells, p.seed, ctx);
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

PolygonMap generate_island(const IslandParams& p, const Heightfield* mask, const ExecContext* ctx,
                           std::vector<double>* lloyd_energy) {
  const glm::dvec2 lo = p.min_corner, hi = p.min_corner + p.size;
  std::vector<glm::dvec2> sites = island_sites(p, ctx);
  if (ctx) ctx->progress(0.1);
  PolygonMap map = relaxed_voronoi_diagram(std::move(sites), lo, hi, p.relaxation, lloyd_energy, ctx);
  if (ctx) ctx->progress(0.8);
  classify_island(map, p, mask, ctx);
  return map;
}

}  // namespace orogen::island
