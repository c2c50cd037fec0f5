// Depression filling across tiles (nodes/hydrology/tile_fill.h, Barnes 2016): each tile floods itself, the spill
// graphs of all tiles are solved once, each tile applies the spill levels; put together, the tiles must equal the
// whole-domain Priority-Flood (Flat) bit for bit, for every tiling, on terrains whose depressions and flats cross
// tile borders and corners. Then the FillDepressions and Lakes nodes across tiles (lakes joined and numbered
// across tiles, nodes/hydrology/tile_lakes.h) against the whole-domain nodes.
#include <bit>
#include <cstring>
#include <deque>
#include <map>
#include <queue>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "graph/domain.h"
#include "graph/node_type.h"
#include "graph/registry.h"
#include "graph/tile_graph.h"
#include "nodes/hydrology/depressions.h"
#include "nodes/hydrology/flow_routing.h"
#include "nodes/hydrology/tile_accumulation.h"
#include "nodes/hydrology/tile_fill.h"
#include "nodes/hydrology/tile_lakes.h"
#include "nodes/hydrology/tile_phases.h"
#include "support/tile_graph_run.h"

namespace orogen::hydrology {
namespace {

using test::algorithm_of;
using test::domain_of;
using test::edge;
using test::same_bits;
using test::Terrain;
using test::terrain;

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

// flood_tile's definition, written plainly: a priority queue of (level, cell) pairs, a pit queue and a FIFO of slope
// cells (those with no unlabelled neighbour lower when they leave it flood at once, the others join the priority
// queue) ahead of it, every neighbour found with bounds checks, the spill edges in an
// ordered map. The labels, levels and edges of the real one (a packed key queue, unchecked interior neighbours, hashed
// edges) must be these, bit for bit.
TileFlood plain_flood(const std::vector<float>& z, const TileRect& rect, const std::vector<std::uint8_t>& drained) {
  const int w = rect.size.x, h = rect.size.y;
  const auto is_drained = [&](std::size_t c) { return !drained.empty() && drained[c] != 0; };
  struct Entry {
    float level;
    std::size_t cell;
    bool operator>(const Entry& o) const { return level > o.level || (level == o.level && cell > o.cell); }
  };
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  TileFlood f;
  f.graph.rect = rect;
  f.level = z;
  f.label.assign(z.size(), -1);
  const auto perimeter = perimeter_cells(rect.size);
  const auto drained_label = static_cast<std::int32_t>(perimeter.size());
  std::map<std::pair<std::int32_t, std::int32_t>, float> edges;
  for (std::size_t k = 0; k < perimeter.size(); ++k) {
    const auto c = static_cast<std::size_t>(perimeter[k]);
    f.label[c] = static_cast<std::int32_t>(k);
    f.graph.perimeter.push_back(z[c]);
    queue.push({z[c], c});
    if (is_drained(c)) edges.emplace(std::make_pair(static_cast<std::int32_t>(k), drained_label), z[c]);
  }
  const auto neighbours = [&](std::size_t c, auto&& fn) {
    const int i = static_cast<int>(c % w), j = static_cast<int>(c / w);
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di)
        if ((di != 0 || dj != 0) && i + di >= 0 && j + dj >= 0 && i + di < w && j + dj < h)
          fn(static_cast<std::size_t>(j + dj) * w + static_cast<std::size_t>(i + di));
  };
  if (!drained.empty())
    for (std::size_t c = 0; c < z.size(); ++c) {
      if (!is_drained(c) || f.label[c] >= 0) continue;
      bool border = false;
      neighbours(c, [&](std::size_t n) { border = border || !is_drained(n); });
      if (border) f.label[c] = drained_label, queue.push({z[c], c});
    }
  std::deque<std::size_t> pit, slope;
  std::vector<bool> done(z.size(), false);
  while (!queue.empty() || !pit.empty() || !slope.empty()) {
    std::size_t c;
    bool from_slope = false;
    if (!pit.empty()) {
      c = pit.front(), pit.pop_front();
    } else if (!slope.empty()) {
      c = slope.front(), slope.pop_front();
      // A cell above its flooder's level floods on at once unless it still has an unflooded lower neighbour: then
      // it waits in the priority queue.
      bool lower = false;
      neighbours(c, [&](std::size_t m) {
        if (f.label[m] < 0 && z[m] < z[c] && !(is_drained(c) && is_drained(m))) lower = true;
      });
      if (lower) {
        queue.push({f.level[c], c});
        continue;
      }
      from_slope = true;
    } else {
      c = queue.top().cell, queue.pop();
    }
    if (done[c]) continue;
    done[c] = true;
    neighbours(c, [&](std::size_t n) {
      if (f.label[n] < 0) {
        if (is_drained(c) && is_drained(n)) return;
        f.label[n] = f.label[c];
        f.level[n] = std::max(z[n], f.level[c]);
        if (f.level[n] == f.level[c] && !from_slope)
          pit.push_back(n);
        else
          slope.push_back(n);
      } else if (f.label[n] != f.label[c]) {
        const float level = std::max(f.level[c], f.level[n]);
        auto [it, fresh] = edges.emplace(std::minmax(f.label[c], f.label[n]), level);
        if (!fresh) it->second = std::min(it->second, level);
      }
    });
  }
  for (const auto& [pair, level] : edges) f.graph.edges.push_back({pair.first, pair.second, level});
  return f;
}

// Terrains that exercise the order of the queue: fBm-like noise, plateaus of equal heights (ties by cell), heights
// of both signs with -0 and +0 among them, with and without drained cells.
TEST(TileFill, FloodTileEqualsAPlainPriorityFloodBitForBit) {
  std::mt19937 rng(12);
  for (int trial = 0; trial < 24; ++trial) {
    const glm::ivec2 size{3 + static_cast<int>(rng() % 60), 2 + static_cast<int>(rng() % 50)};
    std::vector<float> z(static_cast<std::size_t>(size.x) * size.y);
    const int levels = trial % 3 == 0 ? 4 : 1000;  // few distinct heights: wide plateaus and ties
    for (float& v : z) {
      v = static_cast<float>(static_cast<int>(rng() % levels) - levels / 2) * 0.25f;
      if (v == 0.0f && rng() % 2) v = -0.0f;
    }
    std::vector<std::uint8_t> drained;
    if (trial % 2 == 1) {
      drained.resize(z.size());
      for (auto& d : drained) d = rng() % 3 == 0;
    }
    const TileRect rect{{static_cast<int>(rng() % 7), static_cast<int>(rng() % 7)}, size};
    const TileFlood mine = flood_tile(z, rect, drained), theirs = plain_flood(z, rect, drained);
    SCOPED_TRACE("trial " + std::to_string(trial));
    EXPECT_EQ(mine.label, theirs.label);
    EXPECT_TRUE(same_bits(mine.level, theirs.level));
    EXPECT_TRUE(same_bits(mine.graph.perimeter, theirs.graph.perimeter));
    ASSERT_EQ(mine.graph.edges.size(), theirs.graph.edges.size());
    for (std::size_t k = 0; k < mine.graph.edges.size(); ++k) {
      EXPECT_EQ(mine.graph.edges[k].a, theirs.graph.edges[k].a);
      EXPECT_EQ(mine.graph.edges[k].b, theirs.graph.edges[k].b);
      EXPECT_EQ(std::bit_cast<std::uint32_t>(mine.graph.edges[k].level),
                std::bit_cast<std::uint32_t>(theirs.graph.edges[k].level));
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

// FillDepressions (fill, flat) and Lakes through their registered tile-graph algorithms (graph/tile_graph.h,
// nodes/hydrology/fill_across_tiles.cpp), every message passing through its bytes: put together, the tiles' outputs
// must equal the whole-domain node's outputs bit for bit, lake numbers included.
struct NodeOutputs {
  std::vector<float> out, depth, id;
};

NodeOutputs across_tiles(const TileGraphAlgorithm& algorithm, const Terrain& t, glm::ivec2 counts,
                         int* rounds_run = nullptr) {
  auto joined = test::run_across_tiles(algorithm, t, counts, 1, rounds_run);
  EXPECT_EQ(joined.size(), 3u);
  joined.resize(3);
  return {std::move(joined[0]), std::move(joined[1]), std::move(joined[2])};
}

NodeOutputs whole_domain(const FillResult& r) { return {r.out->data, r.depth->data, r.lake_id->data}; }

void expect_same(const NodeOutputs& tiled, const NodeOutputs& whole) {
  EXPECT_TRUE(same_bits(tiled.out, whole.out)) << "out";
  EXPECT_TRUE(same_bits(tiled.depth, whole.depth)) << "water_depth";
  EXPECT_TRUE(same_bits(tiled.id, whole.id)) << "lake_id";
}

// Distinct lake numbers, and whether one of them lies in several tiles of `counts`.
std::pair<int, bool> lakes_and_crossing(const NodeOutputs& o, glm::ivec2 size, glm::ivec2 counts) {
  std::map<int, std::set<int>> tiles_of;
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i)
      if (const int id = static_cast<int>(o.id[static_cast<std::size_t>(j) * size.x + i]); id > 0) {
        const int ti = std::min(counts.x - 1, i * counts.x / size.x),
                  tj = std::min(counts.y - 1, j * counts.y / size.y);
        tiles_of[id].insert(tj * counts.x + ti);
      }
  bool crossing = false;
  for (const auto& [id, tiles] : tiles_of) crossing = crossing || tiles.size() >= 3;
  return {static_cast<int>(tiles_of.size()), crossing};
}

TEST(FillAcrossTiles, FillDepressionsAndLakesEqualTheWholeDomainNodesOnEveryTiling) {
  const std::vector<glm::ivec2> tilings = {{1, 1}, {2, 2}, {3, 2}, {4, 3}, {1, 4}, {7, 6}};
  for (const glm::ivec2 size : {glm::ivec2(41, 33), glm::ivec2(129, 97)})
    for (int levels : {0, 4}) {
      const Terrain t = terrain(size, 5, levels);
      const Domain whole = domain_of(t);
      Heightfield ground(whole);
      ground.data = t.z;
      const NodeOutputs fill = whole_domain(fill_depressions(ground, FillParams{false, false, 0.0}));
      // Lakes at least 2 cm deep and 3 cells large: some small lakes go, the large ones that span tiles stay.
      const LakesParams rule{0.02, 3 * 100.0};
      const FillResult lake_result = lakes(ground, rule);
      const NodeOutputs kept = whole_domain(lake_result);
      const auto all_lakes = lakes_and_crossing(fill, size, {3, 2}).first;
      ASSERT_GT(lake_result.lakes, 1);
      ASSERT_LT(lake_result.lakes, all_lakes) << "the rule must drop some lakes for the test to mean something";
      const auto fill_algorithm = algorithm_of("FillDepressions", {{"flats", std::string("flat")}}, whole);
      const auto lakes_algorithm =
          algorithm_of("Lakes", {{"min_depth", rule.min_depth}, {"min_area", rule.min_area}}, whole);
      ASSERT_TRUE(fill_algorithm && lakes_algorithm);
      for (const glm::ivec2 counts : tilings) {
        SCOPED_TRACE(std::to_string(size.x) + "x" + std::to_string(size.y) + " levels " + std::to_string(levels) +
                     " tiles " + std::to_string(counts.x) + "x" + std::to_string(counts.y));
        expect_same(across_tiles(*fill_algorithm, t, counts), fill);
        expect_same(across_tiles(*lakes_algorithm, t, counts), kept);
        if (counts.x * counts.y >= 6) {
          EXPECT_TRUE(lakes_and_crossing(fill, size, counts).second);
        }
      }
    }
}

// FillDepressions with its default epsilon flats across tiles: the spill graphs give the flat levels, then rounds
// relax the epsilon surface until no tile's perimeter value falls. Bit for bit the whole-domain node on every
// tiling, on terrains made of ties (integer levels: flats that span tiles and cross their corners, lakes with flat
// floors) and continuous ones; a lake whose epsilon gradient crosses three tiles needs several rounds.
TEST(FillAcrossTiles, EpsilonFillEqualsTheWholeDomainNodeOnEveryTiling) {
  const std::vector<glm::ivec2> tilings = {{1, 1}, {2, 2}, {3, 2}, {4, 3}, {1, 4}, {7, 6}};
  int most_rounds = 0;
  for (const glm::ivec2 size : {glm::ivec2(41, 33), glm::ivec2(64, 64), glm::ivec2(129, 97)})
    for (unsigned seed : {5u, 6u})
      for (int levels : {0, 2, 4}) {
        const Terrain t = terrain(size, seed, levels);
        const Domain whole = domain_of(t);
        Heightfield ground(whole);
        ground.data = t.z;
        const NodeOutputs fill = whole_domain(fill_depressions(ground, FillParams{false, true, 0.0}));
        ASSERT_FALSE(same_bits(fill.out, whole_domain_fill(t))) << "the epsilon surface must differ from the flat one";
        const auto algorithm = algorithm_of("FillDepressions", {}, whole);  // epsilon by default
        ASSERT_TRUE(algorithm);
        for (const glm::ivec2 counts : tilings) {
          SCOPED_TRACE(std::to_string(size.x) + "x" + std::to_string(size.y) + " seed " + std::to_string(seed) +
                       " levels " + std::to_string(levels) + " tiles " + std::to_string(counts.x) + "x" +
                       std::to_string(counts.y));
          int rounds = 0;
          expect_same(across_tiles(*algorithm, t, counts, &rounds), fill);
          most_rounds = std::max(most_rounds, rounds);
        }
      }
  EXPECT_GE(most_rounds, 5) << "some surface must need values from tiles beyond the neighbours";
}

// A closed basin whose flat floor spans all four tiles of 2x2 around their common corner and drains through one
// notch: the epsilon surface rises away from the notch across the tile borders, so the tiles away from the notch
// learn their gradient from the others; and a flat island on the corner of four tiles.
TEST(FillAcrossTiles, EpsilonLakeAndPlateauOnTheCornerOfFourTiles) {
  Terrain t{{33, 33}, std::vector<float>(33 * 33, 6.0f)};
  for (int j = 0; j < 33; ++j)
    for (int i = 0; i < 33; ++i) {
      float& z = t.z[static_cast<std::size_t>(j) * 33 + i];
      if (i >= 8 && j >= 8 && i <= 24 && j <= 24) z = (i == 8 || j == 8 || i == 24 || j == 24) ? 5.0f : 0.0f;
      if (i >= 12 && j >= 12 && i <= 20 && j <= 20) z = 3.0f;  // a plateau in the lake (an island)
      if (j < 4 || i < 4) z = 7.0f - 0.1f * static_cast<float>(std::min(i, j));
    }
  t.z[16 * 33 + 8] = 2.0f;  // the notch
  for (int i = 0; i < 8; ++i) t.z[16 * 33 + static_cast<std::size_t>(i)] = 1.0f;
  const Domain whole = domain_of(t);
  Heightfield ground(whole);
  ground.data = t.z;
  const NodeOutputs fill = whole_domain(fill_depressions(ground, FillParams{false, true, 0.0}));
  const auto algorithm = algorithm_of("FillDepressions", {}, whole);
  ASSERT_TRUE(algorithm);
  for (const glm::ivec2 counts : {glm::ivec2(2, 2), glm::ivec2(3, 3), glm::ivec2(4, 3)}) {
    const NodeOutputs tiled = across_tiles(*algorithm, t, counts);
    expect_same(tiled, fill);
    // No undrained cell: every cell but the border has a strictly lower neighbour.
    for (int j = 1; j < 32; ++j)
      for (int i = 1; i < 32; ++i) {
        bool lower = false;
        for (int k = 0; k < 8; ++k)
          lower |= tiled.out[static_cast<std::size_t>(j + kDj[k]) * 33 + i + kDi[k]] <
                   tiled.out[static_cast<std::size_t>(j) * 33 + i];
        ASSERT_TRUE(lower) << i << "," << j;
      }
  }
  // The island's flat top rises by ulps towards its middle (four cells from its shore); the lake stands at its notch.
  EXPECT_EQ(fill.out[16 * 33 + 16],
            std::nextafter(std::nextafter(std::nextafter(std::nextafter(3.0f, 4.0f), 4.0f), 4.0f), 4.0f));
  EXPECT_GT(fill.out[10 * 33 + 10], 2.0f);
  EXPECT_LT(fill.out[10 * 33 + 10], 2.0001f);
}

TEST(FillAcrossTiles, EpsilonPerimeterValuesTravelAsCheckedBytes) {
  const Terrain t = terrain({33, 33}, 4, 4);
  const TileRect a{{0, 0}, {17, 33}}, b{{16, 0}, {17, 33}};
  const auto cut = [&](const TileRect& r) {
    std::vector<float> z;
    for (int j = 0; j < r.size.y; ++j)
      for (int i = 0; i < r.size.x; ++i) z.push_back(t.z[static_cast<std::size_t>(j) * 33 + r.first.x + i]);
    return z;
  };
  TileEpsilon ea(cut(a), a, {33, 33}), eb(cut(b), b, {33, 33});
  const std::vector<std::string> messages = {ea.message(), eb.message()};
  EXPECT_TRUE(perimeter_minima_fell(message_views(messages)));
  const auto answers = solve_perimeter_minima(message_views(messages), {33, 33});
  EXPECT_THROW(solve_perimeter_minima(message_views({messages[0].substr(0, messages[0].size() - 1)}), {33, 33}),
               std::invalid_argument);
  EXPECT_THROW(solve_perimeter_minima(message_views({messages[0] + "x"}), {33, 33}), std::invalid_argument);
  EXPECT_THROW(solve_perimeter_minima(message_views({messages[0]}), {16, 33}),
               std::invalid_argument);  // outside the domain
  EXPECT_THROW(ea.answer(answers[0] + "x"), std::invalid_argument);
  ea.answer(answers[0]);
  eb.answer(answers[1]);
  // Nothing new to say after an answer that lowered nothing it had not sent.
  TileEpsilon alone(cut({{0, 0}, {33, 33}}), {{0, 0}, {33, 33}}, {33, 33});
  const std::vector<std::string> first = {alone.message()};
  alone.answer(solve_perimeter_minima(message_views(first), {33, 33})[0]);
  EXPECT_FALSE(perimeter_minima_fell(message_views({alone.message()})));
}

// Every mode runs across tiles (carving: tests/test_tile_breach.cpp).
TEST(FillAcrossTiles, EveryModeRunsAcrossTiles) {
  const Domain whole = Domain::from_extent({0, 0}, {640, 640}, {65, 65});
  EXPECT_NE(algorithm_of("FillDepressions", {}, whole), nullptr);  // epsilon by default
  EXPECT_NE(algorithm_of("FillDepressions", {{"flats", std::string("flat")}, {"mode", std::string("carve")}}, whole),
            nullptr);
  EXPECT_NE(algorithm_of("FillDepressions", {{"mode", std::string("carve")}}, whole), nullptr);
  EXPECT_NE(algorithm_of("FillDepressions", {{"flats", std::string("flat")}}, whole), nullptr);
}

TEST(FillAcrossTiles, LakeFiguresAreCheckedAndTravelAsBytes) {
  const Terrain t = terrain({33, 33}, 4, 4);
  std::vector<float> water = whole_domain_fill(t);
  const TileRect rect{{0, 0}, {33, 33}};
  const auto labels = label_tile_lakes(water, t.z, rect, {33, 33});
  ASSERT_FALSE(labels.lakes.first_cell.empty());
  const std::string bytes = encode(labels.lakes);
  EXPECT_EQ(encode(decode_tile_lakes(bytes)), bytes);
  EXPECT_THROW(decode_tile_lakes(std::string_view(bytes).substr(0, bytes.size() - 1)), std::invalid_argument);
  EXPECT_THROW(decode_tile_lakes(bytes + "x"), std::invalid_argument);
  // Every cell of the single tile is owned by it: the counts add up to the wet cells.
  std::int64_t wet = 0, counted = 0;
  for (std::size_t c = 0; c < water.size(); ++c) wet += water[c] > t.z[c];
  for (const auto n : labels.lakes.cells) counted += n;
  EXPECT_EQ(counted, wet);
  // Two tiles that disagree whether a shared sample is under water are refused: two copies of a tile in the
  // middle, whose perimeter crosses the central bowl, one with a wet perimeter sample made dry.
  const TileRect middle{{8, 8}, {17, 17}};
  std::vector<float> mid_water, mid_ground;
  for (int j = 0; j < 17; ++j)
    for (int i = 0; i < 17; ++i) {
      mid_water.push_back(water[static_cast<std::size_t>(8 + j) * 33 + 8 + i]);
      mid_ground.push_back(t.z[static_cast<std::size_t>(8 + j) * 33 + 8 + i]);
    }
  TileLakes a = label_tile_lakes(mid_water, mid_ground, middle, {33, 33}).lakes, b = a;
  const auto wet_at = std::find_if(a.perimeter.begin(), a.perimeter.end(), [](std::int32_t k) { return k > 0; });
  ASSERT_NE(wet_at, a.perimeter.end());
  EXPECT_NO_THROW(solve_tile_lakes({a, b}, {33, 33}, [](float, std::int64_t) { return true; }));
  b.perimeter[static_cast<std::size_t>(wet_at - a.perimeter.begin())] = 0;
  EXPECT_THROW(solve_tile_lakes({a, b}, {33, 33}, [](float, std::int64_t) { return true; }), std::invalid_argument);
  b = a;
  b.perimeter[0] = static_cast<std::int32_t>(b.first_cell.size()) + 1;  // names no lake of the tile
  EXPECT_THROW(solve_tile_lakes({a, b}, {33, 33}, [](float, std::int64_t) { return true; }), std::invalid_argument);
}
// D8 accumulation across tiles (nodes/hydrology/tile_accumulation.h, Barnes 2017) on the epsilon-filled terrains:
// whole cell counts, so bit for bit the whole-domain accumulate_d8 of unit weights on every tiling, and at every
// outlet the number of cells whose D8 path ends there.
TEST(AccumulationAcrossTiles, CountsEqualTheWholeDomainOnEveryTiling) {
  const std::vector<glm::ivec2> tilings = {{1, 1}, {2, 2}, {3, 2}, {4, 3}, {1, 4}, {7, 6}};
  for (const glm::ivec2 size : {glm::ivec2(41, 33), glm::ivec2(129, 97)})
    for (int levels : {0, 2}) {
      Terrain t = terrain(size, 9, levels);
      const FlowGrid g(size.x, size.y);
      fill_depressions(g, t.z, FlatMode::Epsilon);
      const D8Flow f = d8_flow(g, t.z);
      const auto whole = accumulate_d8(g, f, std::vector<float>(g.size(), 1.0f));
      // Outlets: the cells whose D8 path ends at them, counted by following the paths.
      const auto ending = test::cells_ending_at(f.receiver);
      for (const glm::ivec2 counts : tilings) {
        SCOPED_TRACE(std::to_string(size.x) + "x" + std::to_string(size.y) + " levels " + std::to_string(levels) +
                     " tiles " + std::to_string(counts.x) + "x" + std::to_string(counts.y));
        std::vector<TileAccumulation> tiles;
        std::vector<std::string> messages;
        for (int tj = 0; tj < counts.y; ++tj)
          for (int ti = 0; ti < counts.x; ++ti) {
            TileRect r;
            r.first = {edge(ti, size.x, counts.x), edge(tj, size.y, counts.y)};
            r.size = glm::ivec2(edge(ti + 1, size.x, counts.x), edge(tj + 1, size.y, counts.y)) - r.first + 1;
            std::vector<std::uint8_t> direction;
            for (int j = 0; j < r.size.y; ++j)
              for (int i = 0; i < r.size.x; ++i)
                direction.push_back(f.direction[static_cast<std::size_t>(g.index(r.first.x + i, r.first.y + j))]);
            tiles.push_back(start_tile_accumulation(direction, r, size));
            messages.push_back(accumulation_message(tiles.back()));
          }
        const auto answers = solve_tile_accumulation(message_views(messages), size);
        std::vector<std::int64_t> joined(g.size(), -1);
        for (std::size_t k = 0; k < tiles.size(); ++k) {
          const auto acc = finish_tile_accumulation(tiles[k], answers[k]);
          const TileRect& r = tiles[k].rect;
          for (int j = 0; j < r.size.y; ++j)
            for (int i = 0; i < r.size.x; ++i) {
              auto& v = joined[static_cast<std::size_t>(g.index(r.first.x + i, r.first.y + j))];
              const std::int64_t mine = acc[static_cast<std::size_t>(j) * r.size.x + i];
              ASSERT_TRUE(v < 0 || v == mine) << "tiles disagree at " << r.first.x + i << "," << r.first.y + j;
              v = mine;
            }
        }
        for (std::size_t c = 0; c < g.size(); ++c) {
          ASSERT_EQ(static_cast<double>(joined[c]), whole[c]) << "cell " << c;
          if (f.receiver[c] == static_cast<std::int32_t>(c)) {
            ASSERT_EQ(joined[c], ending[c]) << "outlet " << c;
          }
        }
      }
    }
}

TEST(AccumulationAcrossTiles, MalformedMessagesAndLoopsAreRefused) {
  const TileRect r{{0, 0}, {3, 3}};
  std::vector<std::uint8_t> direction(9, kNoDirection);
  direction[4] = 0;  // the centre drains east
  const auto t = start_tile_accumulation(direction, r, {3, 3});
  const std::string m = accumulation_message(t);
  EXPECT_NO_THROW(solve_tile_accumulation(message_views({m}), {3, 3}));
  EXPECT_THROW(solve_tile_accumulation(message_views({m + "x"}), {3, 3}), std::invalid_argument);
  EXPECT_THROW(solve_tile_accumulation(message_views({m.substr(0, m.size() - 1)}), {3, 3}), std::invalid_argument);
  EXPECT_THROW(solve_tile_accumulation(message_views({m}), {2, 3}), std::invalid_argument);
  direction[5] = 4;  // east drains back west: a loop
  EXPECT_THROW(start_tile_accumulation(direction, r, {3, 3}), std::invalid_argument);
  EXPECT_THROW(finish_tile_accumulation(t, "x"), std::invalid_argument);
}

}  // namespace
}  // namespace orogen::hydrology

namespace orogen::hydrology {
namespace {

// perimeter_position is perimeter_index without its array, on every shape a tile can take (a single row or column
// included).
TEST(TilePerimeter, PositionsAreTheIndexWithoutTheArray) {
  for (const glm::ivec2 size :
       {glm::ivec2(1, 1), glm::ivec2(1, 5), glm::ivec2(5, 1), glm::ivec2(2, 2), glm::ivec2(2, 7), glm::ivec2(7, 2),
        glm::ivec2(3, 3), glm::ivec2(6, 4), glm::ivec2(33, 17)}) {
    const auto index = perimeter_index(size);
    for (int j = 0; j < size.y; ++j)
      for (int i = 0; i < size.x; ++i)
        ASSERT_EQ(perimeter_position(size, i, j), index[static_cast<std::size_t>(j * size.x + i)])
            << size.x << "x" << size.y << " at " << i << "," << j;
  }
}

}  // namespace
}  // namespace orogen::hydrology
