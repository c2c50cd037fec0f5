// Depression filling across tiles (nodes/hydrology/tile_fill.h, Barnes 2016): each tile floods itself, the spill
// graphs of all tiles are solved once, each tile applies the spill levels; put together, the tiles must equal the
// whole-domain Priority-Flood (Flat) bit for bit, for every tiling, on terrains whose depressions and flats cross
// tile borders and corners.
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "graph/domain.h"
#include "nodes/hydrology/flow_routing.h"
#include "nodes/hydrology/tile_fill.h"

namespace orogen::hydrology {
namespace {

struct Terrain {
  glm::ivec2 size;
  std::vector<float> z;
};

// Tile I of N over W samples: [floor(I (W-1) / N), floor((I+1) (W-1) / N)] (cli/tiling.h).
int edge(int t, int samples, int tiles) { return static_cast<int>(static_cast<long long>(t) * (samples - 1) / tiles); }

std::vector<float> whole_domain_fill(const Terrain& t) {
  std::vector<float> z = t.z;
  const Domain d = Domain::from_extent({0, 0}, {10.0 * (t.size.x - 1), 10.0 * (t.size.y - 1)}, t.size);
  fill_depressions(FlowGrid::of(d), z, FlatMode::Flat);
  return z;
}

// The three phases over `counts` tiles, the spill graphs passing through their byte form as between ranks.
std::vector<float> tiled_fill(const Terrain& t, glm::ivec2 counts) {
  std::vector<TileRect> rects;
  std::vector<TileFlood> floods;
  std::vector<TileSpillGraph> graphs;
  for (int tj = 0; tj < counts.y; ++tj)
    for (int ti = 0; ti < counts.x; ++ti) {
      TileRect r;
      r.first = {edge(ti, t.size.x, counts.x), edge(tj, t.size.y, counts.y)};
      r.size = glm::ivec2(edge(ti + 1, t.size.x, counts.x), edge(tj + 1, t.size.y, counts.y)) - r.first + 1;
      std::vector<float> z;
      for (int j = 0; j < r.size.y; ++j)
        for (int i = 0; i < r.size.x; ++i)
          z.push_back(t.z[static_cast<std::size_t>(r.first.y + j) * t.size.x + r.first.x + i]);
      floods.push_back(flood_tile(z, r));
      graphs.push_back(decode_spill_graph(encode(floods.back().graph)));
      rects.push_back(r);
    }
  const auto levels = solve_spill_graphs(graphs, t.size);
  std::vector<float> out(t.z.size(), std::numeric_limits<float>::quiet_NaN());
  for (std::size_t k = 0; k < floods.size(); ++k) {
    const auto filled = apply_spill_levels(floods[k], levels[k]);
    const TileRect& r = rects[k];
    for (int j = 0; j < r.size.y; ++j)
      for (int i = 0; i < r.size.x; ++i) {
        float& o = out[static_cast<std::size_t>(r.first.y + j) * t.size.x + r.first.x + i];
        const float v = filled[static_cast<std::size_t>(j) * r.size.x + i];
        EXPECT_TRUE(std::isnan(o) || o == v) << "tiles disagree on a shared sample";
        o = v;
      }
  }
  return out;
}

// Random heights: `levels` > 0 quantizes them to integers (wide flats and ties), else continuous; plus a bowl on
// the domain's centre and a trench along its lower quarter, so depressions span tiles and cross their corners.
Terrain terrain(glm::ivec2 size, unsigned seed, int levels) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Terrain t{size, {}};
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i) {
      float v = u(rng) * 10.0f;
      if (levels > 0) v = std::floor(v * levels / 10.0f);
      const float dx = (i - size.x / 2.0f) / size.x, dy = (j - size.y / 2.0f) / size.y;
      v -= 30.0f * std::max(0.0f, 0.3f - std::sqrt(dx * dx + dy * dy));
      if (std::abs(j - size.y / 4) <= 1 && i > 2 && i < size.x - 3) v -= 8.0f;
      t.z.push_back(v + 0.05f * static_cast<float>(i));
    }
  return t;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(TileFill, EveryTilingEqualsTheWholeDomainFillBitForBit) {
  const std::vector<glm::ivec2> tilings = {{1, 1}, {2, 2}, {3, 2}, {4, 3}, {5, 1}, {1, 4}, {7, 6}};
  for (const glm::ivec2 size : {glm::ivec2(41, 33), glm::ivec2(64, 64), glm::ivec2(129, 97)})
    for (unsigned seed : {1u, 2u})
      for (int levels : {0, 4}) {
        const Terrain t = terrain(size, seed, levels);
        const auto whole = whole_domain_fill(t);
        ASSERT_FALSE(same_bits(whole, t.z)) << "the terrain must have depressions";
        for (const glm::ivec2 counts : tilings) {
          SCOPED_TRACE(std::to_string(size.x) + "x" + std::to_string(size.y) + " seed " + std::to_string(seed) +
                       " levels " + std::to_string(levels) + " tiles " + std::to_string(counts.x) + "x" +
                       std::to_string(counts.y));
          EXPECT_TRUE(same_bits(tiled_fill(t, counts), whole));
        }
      }
}

TEST(TileFill, ALakeAcrossFourTilesFillsToItsSpillAndDrains) {
  // A closed square basin around the centre (the corner of four tiles), rim 5 m with one notch at 2 m.
  Terrain t{{33, 33}, std::vector<float>(33 * 33, 6.0f)};
  for (int j = 8; j <= 24; ++j)
    for (int i = 8; i <= 24; ++i)
      t.z[static_cast<std::size_t>(j) * 33 + i] = (i == 8 || j == 8 || i == 24 || j == 24) ? 5.0f : 0.0f;
  t.z[16 * 33 + 8] = 2.0f;                                                        // the notch, on the west rim
  for (int i = 0; i < 8; ++i) t.z[16 * 33 + static_cast<std::size_t>(i)] = 1.0f;  // a channel out to the border
  const auto out = tiled_fill(t, {2, 2});
  EXPECT_TRUE(same_bits(out, whole_domain_fill(t)));
  EXPECT_EQ(out[16 * 33 + 16], 2.0f);  // the lake stands at its notch
  EXPECT_EQ(out[12 * 33 + 20], 2.0f);
  EXPECT_EQ(out[16 * 33 + 4], 1.0f);  // the channel is not raised
}

TEST(TileFill, SpillGraphsAreSmallAndTheirBytesAreChecked) {
  const Terrain t = terrain({64, 64}, 3, 0);
  const auto f = flood_tile(t.z, {{0, 0}, {64, 64}});
  EXPECT_EQ(f.graph.perimeter.size(), 4u * 63u);  // the perimeter, not the tile
  const std::string bytes = encode(f.graph);
  const auto back = decode_spill_graph(bytes);
  EXPECT_EQ(encode(back), bytes);
  EXPECT_THROW(decode_spill_graph(std::string_view(bytes).substr(0, bytes.size() - 1)), std::invalid_argument);
  EXPECT_THROW(decode_spill_graph(bytes + "x"), std::invalid_argument);
  // Tiles that disagree on a shared sample are refused.
  Terrain u = t;
  auto a = flood_tile(std::vector<float>(u.z.begin(), u.z.end()), {{0, 0}, {64, 64}}).graph;
  auto b = a;
  b.perimeter[0] += 1.0f;
  EXPECT_THROW(solve_spill_graphs({a, b}, {64, 64}), std::invalid_argument);
}

}  // namespace
}  // namespace orogen::hydrology
