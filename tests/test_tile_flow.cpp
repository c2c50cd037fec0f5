// FlowDirection (fill on), FlowAccumulation (every method) and Watersheds across tiles through their registered
// tile-graph algorithms (nodes/hydrology/flow_across_tiles.cpp): the epsilon fill's rounds (or the filled surface an
// earlier flow node kept), a one-sample ring of the filled surface from the tiles around, D8 counts through perimeter
// links (Barnes 2017), D-infinity, MFD and rainfall-weighted shares pulled in neighbour order in rounds, the largest
// area for the flow map, and basin labels through the same links with the cells of each basin added up across tiles.
// Put together, the tiles' outputs must equal the whole-domain functions the nodes call bit for bit, on every tiling,
// on terrains whose lakes, flats and drainage cross tile borders and corners; and the accumulation at every outlet is
// the area that drains to it.
#include <cmath>
#include <cstring>
#include <map>
#include <numeric>
#include <set>

#include <gtest/gtest.h>

#include "evaluator/run_node.h"
#include "graph/tile_bytes.h"
#include "nodes/common/match_domain.h"
#include "nodes/hydrology/flow.h"
#include "nodes/hydrology/tile_basins.h"
#include "nodes/hydrology/tile_ring.h"
#include "nodes/hydrology/tile_shares.h"
#include "nodes/hydrology/tile_surface_memo.h"
#include "nodes/hydrology/tile_phases.h"
#include "support/tile_graph_run.h"

namespace orogen::hydrology {
namespace {

using test::algorithm_of;
using test::domain_of;
using test::same_bits;
using test::Terrain;
using test::terrain;

std::string tiling_text(glm::ivec2 size, int levels, glm::ivec2 counts) {
  return test::tiles_text(size) + " levels " + std::to_string(levels) + " tiles " + test::tiles_text(counts);
}

void expect_same(const std::vector<std::vector<float>>& tiled, const std::vector<HeightfieldPtr>& whole,
                 const std::vector<const char*>& names) {
  ASSERT_EQ(tiled.size(), whole.size());
  for (std::size_t o = 0; o < whole.size(); ++o) {
    ASSERT_TRUE(whole[o]) << names[o];
    EXPECT_TRUE(same_bits(tiled[o], whole[o]->data)) << names[o];
  }
}

TEST(FlowAcrossTiles, FlowDirectionWithFillEqualsTheWholeDomainNodeOnEveryTiling) {
  for (const glm::ivec2 size : {glm::ivec2(41, 33), glm::ivec2(129, 97)})
    for (int levels : {0, 2}) {
      const Terrain t = terrain(size, 11, levels);
      const Domain whole = domain_of(t);
      const Heightfield ground = test::heights_of(t);
      for (const char* method : {"d8", "dinf", "mfd"}) {
        SCOPED_TRACE(method);
        const auto kind = std::string(method) == "d8"     ? FlowMethod::D8
                          : std::string(method) == "dinf" ? FlowMethod::DInfinity
                                                          : FlowMethod::MFD;
        const DirectionResult r = flow_direction(ground, kind, 1.1, true);
        const auto algorithm = algorithm_of("FlowDirection", {{"method", std::string(method)}}, whole);
        ASSERT_TRUE(algorithm);
        for (const glm::ivec2 counts : test::kTilings) {
          SCOPED_TRACE(tiling_text(size, levels, counts));
          forget_filled_surfaces();  // the fill's rounds, not a surface an earlier run kept
          expect_same(test::run_across_tiles(*algorithm, t, counts), {r.angle, r.dx, r.dy, r.slope},
                      {"out", "dx", "dy", "gradient"});
        }
      }
    }
}

TEST(FlowAcrossTiles, D8AccumulationEqualsTheWholeDomainNodeAndSumsToTheAreaOfEachOutlet) {
  int most_tiles_crossed = 0;
  for (const glm::ivec2 size : {glm::ivec2(41, 33), glm::ivec2(129, 97)})
    for (int levels : {0, 2})
      for (bool fill : {true, false})
        for (double max_area : {0.0, 5e4}) {
          SCOPED_TRACE(std::string(fill ? "fill" : "no fill") + " flow_max_area " + std::to_string(max_area));
          const Terrain t = terrain(size, 12, levels);
          const Domain whole = domain_of(t);
          const Heightfield ground = test::heights_of(t);
          AccumulationParams p;
          p.method = FlowMethod::D8;
          p.fill = fill;
          p.flow_max_area = max_area;
          const AccumulationResult r = flow_accumulation(ground, nullptr, p);
          const auto algorithm = algorithm_of(
              "FlowAccumulation", {{"method", std::string("d8")}, {"fill", fill}, {"flow_max_area", max_area}}, whole);
          ASSERT_TRUE(algorithm);
          // The D8 paths of the whole domain: the cells ending at each outlet (or pit), and the tiles they cross.
          const FlowGrid g = FlowGrid::of(whole);
          std::vector<float> z = t.z;
          if (fill) fill_depressions(g, z, FlatMode::Epsilon);
          const D8Flow f = d8_flow(g, z);
          const auto ending = test::cells_ending_at(f.receiver);
          for (const glm::ivec2 counts : test::kTilings) {
            SCOPED_TRACE(tiling_text(size, levels, counts));
            forget_filled_surfaces();  // the fill's rounds, not a surface an earlier run kept
            const auto tiled = test::run_across_tiles(*algorithm, t, counts, 2);
            expect_same(tiled, {r.accumulation, r.flow, r.wetness}, {"out", "flow", "wetness"});
            for (std::size_t c = 0; c < g.size(); ++c)
              if (f.receiver[c] == static_cast<std::int32_t>(c)) {
                ASSERT_EQ(tiled[0][c], static_cast<float>(static_cast<double>(ending[c]) * g.cell_area()))
                    << "outlet " << c;
              }
            if (!fill || counts.x * counts.y < 4) continue;
            for (std::int32_t c = 0; c < static_cast<std::int32_t>(g.size()); c += 7) {
              std::set<int> crossed;
              for (std::int32_t x = c;; x = f.receiver[static_cast<std::size_t>(x)]) {
                crossed.insert(test::tile_of(g.column(x), g.row(x), size, counts));
                if (f.receiver[static_cast<std::size_t>(x)] == x) break;
              }
              most_tiles_crossed = std::max(most_tiles_crossed, static_cast<int>(crossed.size()));
            }
          }
        }
  EXPECT_GE(most_tiles_crossed, 4) << "some drainage must cross several tiles and their corners";
}

// Watersheds: every cell labeled with its D8 outlet through the perimeter links, basins numbered by decreasing area
// over the whole domain (ties by outlet index), the small ones dropped; with filling (outlets on the border only) and
// without (pits too, many of them inside tiles).
TEST(FlowAcrossTiles, WatershedsEqualTheWholeDomainNodeOnEveryTiling) {
  bool crossing = false;
  for (const glm::ivec2 size : {glm::ivec2(41, 33), glm::ivec2(129, 97)})
    for (int levels : {0, 2})
      for (bool fill : {true, false})
        for (double min_area : {0.0, 2000.0}) {
          SCOPED_TRACE(std::string(fill ? "fill" : "no fill") + " min_area " + std::to_string(min_area));
          const Terrain t = terrain(size, 13, levels);
          const Domain whole = domain_of(t);
          const Heightfield ground = test::heights_of(t);
          const WatershedResult r = watersheds(ground, fill, min_area);
          ASSERT_GT(r.basins, 1);
          const auto algorithm = algorithm_of("Watersheds", {{"fill", fill}, {"min_area", min_area}}, whole);
          ASSERT_TRUE(algorithm);
          for (const glm::ivec2 counts : test::kTilings) {
            SCOPED_TRACE(tiling_text(size, levels, counts));
            forget_filled_surfaces();  // the fill's rounds, not a surface an earlier run kept
            const auto tiled = test::run_across_tiles(*algorithm, t, counts);
            expect_same(tiled, {r.id, r.area}, {"out", "area"});
            if (counts.x * counts.y < 4) continue;
            std::map<int, std::set<int>> tiles_of;
            for (int j = 0; j < size.y; ++j)
              for (int i = 0; i < size.x; ++i)
                if (const int id = static_cast<int>(r.id->data[static_cast<std::size_t>(j * size.x + i)]); id > 0)
                  tiles_of[id].insert(test::tile_of(i, j, size, counts));
            for (const auto& [id, tiles] : tiles_of) crossing = crossing || tiles.size() >= 3;
          }
        }
  EXPECT_TRUE(crossing) << "some basin must span three tiles";
}

TEST(FlowAcrossTiles, BasinLinksAndCountsTravelAsCheckedBytes) {
  const TileRect r{{0, 0}, {3, 3}};
  std::vector<std::uint8_t> direction(9, kNoDirection);
  direction[4] = 0;  // the centre drains east, to a border outlet
  direction[3] = 0;  // and the west perimeter cell to the centre: a link from the perimeter to the perimeter
  auto basins = start_tile_basins(start_tile_accumulation(direction, r, {3, 3}));
  const std::string links = basin_links_message(basins);
  const auto answers = solve_basin_links(message_views({links}), {3, 3});
  EXPECT_THROW(solve_basin_links(message_views({links + "x"}), {3, 3}), std::invalid_argument);
  EXPECT_THROW(solve_basin_links(message_views({links.substr(0, links.size() - 1)}), {3, 3}), std::invalid_argument);
  EXPECT_THROW(solve_basin_links(message_views({links}), {2, 3}), std::invalid_argument);
  EXPECT_THROW(solve_basin_links(message_views({links, links}), {3, 3}),
               std::invalid_argument);  // one edge taken twice
  EXPECT_THROW(take_basin_outlets(basins, answers[0] + "x"), std::invalid_argument);
  take_basin_outlets(basins, answers[0]);
  EXPECT_EQ(basins.outlet[4], 5);
  EXPECT_EQ(basins.outlet[3], 5);
  const std::string counts = basin_count_message(basins);
  const auto numbers = solve_basin_counts(message_views({counts}), 1.0, 0.0);
  EXPECT_THROW(solve_basin_counts(message_views({counts + "x"}), 1.0, 0.0), std::invalid_argument);
  std::vector<float> id(9), area(9);
  EXPECT_THROW(basin_maps(basins, numbers[0] + "x", 1.0, id, area), std::invalid_argument);
  basin_maps(basins, numbers[0], 1.0, id, area);
  EXPECT_EQ(id[4], 1.0f);  // the largest basin: the outlet east of the centre, with three cells
  EXPECT_EQ(area[4], 3.0f);
  EXPECT_EQ(id[0], 2.0f);  // then the one-cell basins by outlet index
  EXPECT_EQ(area[0], 1.0f);
}

TEST(FlowAcrossTiles, EveryAccumulationRunsAcrossTiles) {
  const Domain whole = Domain::from_extent({0, 0}, {640, 640}, {65, 65});
  for (const char* method : {"d8", "dinf", "mfd"}) {
    EXPECT_NE(algorithm_of("FlowAccumulation", {{"method", std::string(method)}}, whole), nullptr) << method;
    EXPECT_NE(algorithm_of("FlowAccumulation", {{"method", std::string(method)}, {"fill", false}}, whole), nullptr);
  }
  EXPECT_NE(algorithm_of("FlowDirection", {{"method", std::string("mfd")}}, whole), nullptr);
  EXPECT_EQ(algorithm_of("FlowDirection", {{"fill", false}}, whole), nullptr);  // a local node then
  // A linked rainfall weight runs across the tiles too (by shares); it must lie on the tile.
  EXPECT_TRUE(tile_graph_unlinked_inputs("FlowAccumulation").empty());
  EXPECT_TRUE(tile_graph_unlinked_inputs("FlowDirection").empty());
  EXPECT_NE(algorithm_of("Watersheds", {{"fill", false}}, whole), nullptr);
  const auto algorithm = algorithm_of("FlowAccumulation", {{"method", std::string("mfd")}}, whole);
  const Terrain t = terrain({65, 65}, 17, 0);
  auto h = std::make_shared<Heightfield>(test::heights_of(t));
  h->domain = whole;
  // A rainfall weight on another lattice is resampled onto each tile as the whole-domain node resamples it onto the
  // domain (positions are origin + (first + i) * spacing): the tiles equal the node end to end. One that misses the
  // domain is refused.
  auto other = std::make_shared<Heightfield>(Domain::from_extent({-7, 3}, {650, 600}, {33, 29}));
  for (std::size_t c = 0; c < other->data.size(); ++c) other->data[c] = 0.5f + 0.37f * static_cast<float>(c % 23);
  const NodeRun node =
      run_node("FlowAccumulation", whole, {{"method", std::string("mfd")}},
               {{"in", PortValue(HeightfieldPtr(h))}, {"rainfall_weight", PortValue(HeightfieldPtr(other))}});
  for (const glm::ivec2 counts : {glm::ivec2(3, 2), glm::ivec2(6, 5)}) {
    SCOPED_TRACE("tiles " + test::tiles_text(counts));
    std::vector<std::unique_ptr<TileGraphTile>> tiles;
    for (int tj = 0; tj < counts.y; ++tj)
      for (int ti = 0; ti < counts.x; ++ti) {
        const glm::ivec2 first{test::edge(ti, 65, counts.x), test::edge(tj, 65, counts.y)};
        const glm::ivec2 n = glm::ivec2(test::edge(ti + 1, 65, counts.x), test::edge(tj + 1, 65, counts.y)) - first + 1;
        tiles.push_back(algorithm->start({test::crop(whole, h, first, n), HeightfieldPtr(other)}));
      }
    forget_filled_surfaces();
    test::run_rounds(*algorithm, tiles);
    std::vector<std::vector<float>> joined(3, std::vector<float>(65 * 65, std::numeric_limits<float>::quiet_NaN()));
    for (auto& tile : tiles) {
      const auto outputs = tile->outputs();
      for (std::size_t o = 0; o < 3; ++o)
        test::join_tile_map(joined[o], *std::get<HeightfieldPtr>(outputs[o]), 65, nullptr);
    }
    for (std::size_t o = 0; o < 3; ++o) EXPECT_TRUE(same_bits(joined[o], node.get<Heightfield>(o)->data)) << o;
  }
  auto far = std::make_shared<Heightfield>(Domain::from_extent({5000, 5000}, {5640, 5640}, {33, 33}));
  EXPECT_THROW(algorithm->start({HeightfieldPtr(h), HeightfieldPtr(far)}), std::invalid_argument);
  EXPECT_NO_THROW(algorithm->start({HeightfieldPtr(h), HeightfieldPtr(h)}));
  EXPECT_NO_THROW(algorithm->start({HeightfieldPtr(h), PortValue{}}));
}

// The whole-domain accumulation by shares (flow_shares.h) is the pull of every cell's donors in neighbour order: a
// plain serial reference that visits the cells from the highest down (flow descends) gives the same bits.
TEST(FlowAcrossTiles, WholeDomainSharesArePulledInNeighbourOrder) {
  const Terrain t = terrain({57, 43}, 21, 0);
  const FlowGrid g = FlowGrid::of(domain_of(t));
  std::vector<float> z = t.z;
  fill_depressions(g, z, FlatMode::Epsilon);
  std::vector<float> weight(g.size());
  for (std::size_t c = 0; c < g.size(); ++c) weight[c] = 50.0f + static_cast<float>(c % 13);
  std::vector<std::int32_t> order(g.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::int32_t a, std::int32_t b) { return z[a] > z[b]; });
  for (const FlowMethod m : {FlowMethod::DInfinity, FlowMethod::MFD}) {
    const RoutingOptions opt{m, 1.7, {}};
    const auto acc = accumulate(g, z, opt, weight);
    std::vector<double> ref(g.size(), 0.0);
    for (const std::int32_t c : order) {
      double sum = weight[static_cast<std::size_t>(c)];
      for (int k = 0; k < 8; ++k) {
        const int i = g.column(c) + kDi[k], j = g.row(c) + kDj[k];
        if (!g.inside(i, j)) continue;
        int nb[8];
        double fr[8];
        const int n = flow_proportions(g, z, i, j, opt, nb, fr);
        for (int q = 0; q < n; ++q)
          if (nb[q] == opposite(k)) {
            const double share = m == FlowMethod::DInfinity && n == 2
                                     ? (q == 0 ? static_cast<double>(static_cast<float>(fr[0]))
                                               : 1.0 - static_cast<double>(static_cast<float>(fr[0])))
                                     : fr[q];
            sum += ref[static_cast<std::size_t>(g.index(i, j))] * share;
          }
      }
      ref[static_cast<std::size_t>(c)] = sum;
    }
    EXPECT_EQ(std::memcmp(acc.data(), ref.data(), acc.size() * sizeof(double)), 0)
        << (m == FlowMethod::MFD ? "mfd" : "dinf");
  }
}

// A valley that meanders along the border between tile columns (and the trench and bowl of the random terrains):
// MFD and D-infinity paths cross the border at almost every step, so the shares go back and forth in many rounds.
Terrain border_valley(glm::ivec2 size, unsigned seed) {
  Terrain t = terrain(size, seed, 0);
  const float axis = static_cast<float>(test::edge(1, size.x, 2));
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i) {
      const float meander = axis + 1.5f * std::sin(0.7f * static_cast<float>(j));
      t.z[static_cast<std::size_t>(j * size.x + i)] = 0.3f * t.z[static_cast<std::size_t>(j * size.x + i)] +
                                                      4.0f * std::abs(static_cast<float>(i) - meander) +
                                                      1.0f * static_cast<float>(j);
    }
  return t;
}

// D-infinity, MFD and rainfall-weighted D8 accumulation across tiles: the shares pulled in neighbour order through the
// tiles' borders, round after round, equal the whole-domain node bit for bit on every tiling (tiles two samples wide
// too), with and without filling and a rainfall weight; and the area reaching the outlets is the domain's.
TEST(FlowAcrossTiles, AccumulationBySharesEqualsTheWholeDomainNodeOnEveryTiling) {
  int most_rounds = 0;
  struct Case {
    const char* method;
    FlowMethod kind;
    bool rain;
  };
  for (const Case& k : {Case{"mfd", FlowMethod::MFD, false}, Case{"dinf", FlowMethod::DInfinity, false},
                        Case{"mfd", FlowMethod::MFD, true}, Case{"dinf", FlowMethod::DInfinity, true},
                        Case{"d8", FlowMethod::D8, true}})
    for (const glm::ivec2 size : {glm::ivec2(41, 33), glm::ivec2(97, 65)})
      for (int shape : {0, 1, 2})
        for (bool fill : {true, false}) {
          if (size.x > 41 && (k.rain || shape == 1)) continue;  // the larger terrain without the rarer cases
          if (k.rain && !fill) continue;
          SCOPED_TRACE(std::string(k.method) + (k.rain ? " rainfall " : " ") + (fill ? "fill" : "no fill") +
                       " terrain " + std::to_string(shape));
          const Terrain t = shape == 2 ? border_valley(size, 14) : terrain(size, 14, shape == 1 ? 2 : 0);
          const Domain whole = domain_of(t);
          const Heightfield ground = test::heights_of(t);
          Heightfield rain(whole);
          for (std::size_t c = 0; c < rain.data.size(); ++c) rain.data[c] = 0.25f + 0.1f * static_cast<float>(c % 17);
          rain.data[5] = -1.0f;  // clamped to 0
          const double max_area = shape == 1 ? 5e4 : 0.0;
          AccumulationParams p;
          p.method = k.kind;
          p.fill = fill;
          p.exponent = 1.1;
          p.flow_max_area = max_area;
          const AccumulationResult r = flow_accumulation(ground, k.rain ? &rain : nullptr, p);
          const auto algorithm =
              algorithm_of("FlowAccumulation",
                           {{"method", std::string(k.method)}, {"fill", fill}, {"flow_max_area", max_area}}, whole);
          ASSERT_TRUE(algorithm);
          for (const glm::ivec2 counts : test::kTilings) {
            SCOPED_TRACE(tiling_text(size, shape, counts));
            int rounds = 0;
            forget_filled_surfaces();  // the fill's rounds, not a surface an earlier run kept
            const auto tiled =
                test::run_across_tiles(*algorithm, t, counts, 2, &rounds, {k.rain ? &rain.data : nullptr});
            expect_same(tiled, {r.accumulation, r.flow, r.wetness}, {"out", "flow", "wetness"});
            most_rounds = std::max(most_rounds, rounds);
          }
          if (!fill || k.rain) continue;
          // With filling only the border drains: what reaches it is the whole domain's area.
          const FlowGrid g = FlowGrid::of(whole);
          double drained = 0.0;
          for (int j = 0; j < g.ny; ++j)
            for (int i = 0; i < g.nx; ++i)
              if (g.on_border(i, j)) drained += r.accumulation->data[static_cast<std::size_t>(g.index(i, j))];
          // (minus what the border cells pass to each other: none, they are outlets)
          EXPECT_NEAR(drained / (static_cast<double>(g.size()) * g.cell_area()), 1.0, 1e-5);
        }
  // The fill's rounds, the ring, the edges and then many rounds of shares crossing the valley's tile border.
  EXPECT_GE(most_rounds, 30) << "some flow must cross tile borders many times";
}

// The shares' dataflow alone, in double (the node's float outputs would hide a difference in the last bits of a sum):
// every tile's accumulation equals accumulate() on the whole domain bit for bit, on every tiling.
TEST(FlowAcrossTiles, SharesInDoubleEqualTheWholeDomainOnEveryTiling) {
  for (const FlowMethod m : {FlowMethod::MFD, FlowMethod::DInfinity, FlowMethod::D8})
    for (int shape : {0, 1, 2})
      for (bool weighted : {false, true}) {
        SCOPED_TRACE("method " + std::to_string(static_cast<int>(m)) + " terrain " + std::to_string(shape) +
                     (weighted ? " weighted" : ""));
        const glm::ivec2 size(41, 33);
        const Terrain t = shape == 2 ? border_valley(size, 15) : terrain(size, 15, shape == 1 ? 2 : 0);
        const FlowGrid g = FlowGrid::of(domain_of(t));
        std::vector<float> z = t.z;
        fill_depressions(g, z, FlatMode::Epsilon);
        std::vector<float> weight;
        if (weighted)
          for (std::size_t c = 0; c < g.size(); ++c) weight.push_back(30.0f + 7.0f * static_cast<float>(c % 11));
        const RoutingOptions opt{m, 1.3, {}};
        const auto whole = accumulate(g, z, opt, weight);
        for (const glm::ivec2 counts : test::kTilings) {
          SCOPED_TRACE(tiling_text(size, shape, counts));
          std::vector<TileRect> rects;
          std::vector<std::unique_ptr<TileShares>> tiles;
          for (int tj = 0; tj < counts.y; ++tj)
            for (int ti = 0; ti < counts.x; ++ti) {
              const glm::ivec2 first{test::edge(ti, size.x, counts.x), test::edge(tj, size.y, counts.y)};
              const TileRect r{
                  first,
                  glm::ivec2(test::edge(ti + 1, size.x, counts.x), test::edge(tj + 1, size.y, counts.y)) - first + 1};
              const TileRect ringed = ringed_rect(r, size);
              std::vector<float> rz, w;
              for (int j = 0; j < ringed.size.y; ++j)
                for (int i = 0; i < ringed.size.x; ++i)
                  rz.push_back(z[static_cast<std::size_t>(g.index(ringed.first.x + i, ringed.first.y + j))]);
              if (weighted)
                for (int j = 0; j < r.size.y; ++j)
                  for (int i = 0; i < r.size.x; ++i)
                    w.push_back(weight[static_cast<std::size_t>(g.index(first.x + i, first.y + j))]);
              rects.push_back(r);
              tiles.push_back(std::make_unique<TileShares>(rz, r, size, g.dx, g.dy, opt, w));
            }
          std::vector<std::string> messages;
          for (auto& tile : tiles) messages.push_back(tile->edges_message());
          auto answers = solve_share_edges(message_views(messages), size);
          for (std::size_t k = 0; k < tiles.size(); ++k) tiles[k]->take_edges(answers[k]);
          for (int round = 0;; ++round) {
            ASSERT_LT(round, 10000);
            messages.clear();
            for (auto& tile : tiles) messages.push_back(tile->shares_message());
            answers = solve_shares(message_views(messages), size);
            for (std::size_t k = 0; k < tiles.size(); ++k) tiles[k]->take_shares(answers[k]);
            if (shares_done(message_views(messages))) break;
          }
          for (std::size_t k = 0; k < tiles.size(); ++k) {
            const auto acc = tiles[k]->take_accumulation();
            for (int j = 0; j < rects[k].size.y; ++j)
              for (int i = 0; i < rects[k].size.x; ++i) {
                const double a = acc[static_cast<std::size_t>(j * rects[k].size.x + i)];
                const double b = whole[static_cast<std::size_t>(g.index(rects[k].first.x + i, rects[k].first.y + j))];
                ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << "tile " << k << " cell " << i << "," << j;
              }
          }
        }
      }
}

TEST(FlowAcrossTiles, SharesTravelAsCheckedBytes) {
  // A 5 x 3 domain in two tiles sharing column 2, falling to the east: flow crosses from tile 0 into tile 1 only.
  const glm::ivec2 domain(5, 3);
  const std::vector<TileRect> rects = {{{0, 0}, {3, 3}}, {{2, 0}, {3, 3}}};
  const std::vector<float> z = {9, 8, 7, 6, 5, 9, 8, 7, 6, 5, 9, 8, 7, 6, 5};
  const RoutingOptions opt{FlowMethod::MFD, 1.1, {}};
  std::vector<std::unique_ptr<TileShares>> tiles;
  for (const TileRect& r : rects) {
    const TileRect ringed = ringed_rect(r, domain);
    std::vector<float> rz;
    for (int j = 0; j < ringed.size.y; ++j)
      for (int i = 0; i < ringed.size.x; ++i) rz.push_back(z[(ringed.first.y + j) * domain.x + ringed.first.x + i]);
    tiles.push_back(std::make_unique<TileShares>(rz, r, domain, 1.0, 1.0, opt, std::vector<float>{}));
  }
  std::vector<std::string> edges = {tiles[0]->edges_message(), tiles[1]->edges_message()};
  EXPECT_THROW(solve_share_edges(message_views({edges[0] + "x", edges[1]}), domain), std::invalid_argument);
  EXPECT_THROW(solve_share_edges(message_views({edges[0]}), {2, 2}), std::invalid_argument);  // outside the domain
  const auto answers = solve_share_edges(message_views(edges), domain);
  EXPECT_THROW(tiles[1]->take_edges(answers[1] + "x"), std::invalid_argument);
  EXPECT_THROW(tiles[1]->take_edges(answers[0]), std::invalid_argument);  // not its edges
  for (std::size_t t = 0; t < 2; ++t) tiles[t]->take_edges(answers[t]);
  EXPECT_TRUE(tiles[0]->done());
  EXPECT_FALSE(tiles[1]->done());  // column 2 waits for column 1, held by tile 0 alone
  std::vector<std::string> shares = {tiles[0]->shares_message(), tiles[1]->shares_message()};
  EXPECT_FALSE(shares_done(message_views(shares)));
  EXPECT_THROW(solve_shares(message_views({shares[0].substr(0, shares[0].size() - 1), shares[1]}), domain),
               std::invalid_argument);
  const auto delivered = solve_shares(message_views(shares), domain);
  EXPECT_THROW(tiles[0]->take_shares(delivered[1]), std::invalid_argument);  // tile 0 waits for nothing
  tiles[1]->take_shares(delivered[1]);
  EXPECT_TRUE(tiles[1]->done());
  // No share moved while a tile waits: a cycle, refused.
  EXPECT_THROW(solve_shares(message_views({tiles[0]->shares_message(),
                                           shares[1].substr(0, 1) + tiles[0]->shares_message().substr(1)}),
                            domain),
               std::invalid_argument);
  const auto whole = accumulate(FlowGrid(5, 3), z, opt);
  const auto right = tiles[1]->take_accumulation();
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) EXPECT_EQ(right[j * 3 + i], whole[j * 5 + 2 + i]);
}

// A flow node keeps each tile's filled surface; the next flow node on the same heights takes it instead of filling
// again (one round of agreement, then the ring), and fills when any tile's heights differ, so no tile ever takes a
// surface of other heights and all tiles stay in step.
TEST(FlowAcrossTiles, TheFilledSurfaceIsSharedBetweenFlowNodesOnTheSameHeights) {
  const Terrain t = terrain({41, 33}, 16, 2);
  const Domain whole = domain_of(t);
  const Heightfield ground = test::heights_of(t);
  AccumulationParams p;
  p.method = FlowMethod::MFD;
  const AccumulationResult r = flow_accumulation(ground, nullptr, p);
  const auto direction = algorithm_of("FlowDirection", {}, whole);
  const auto accumulation = algorithm_of("FlowAccumulation", {{"method", std::string("mfd")}}, whole);
  for (const glm::ivec2 counts : {glm::ivec2(1, 1), glm::ivec2(3, 2), glm::ivec2(40, 32)}) {
    SCOPED_TRACE(tiling_text(t.size, 2, counts));
    forget_filled_surfaces();
    int filling = 0, sharing = 0, again = 0;
    const auto fresh = test::run_across_tiles(*accumulation, t, counts, 2, &filling);
    forget_filled_surfaces();
    test::run_across_tiles(*direction, t, counts);
    const auto shared = test::run_across_tiles(*accumulation, t, counts, 2, &sharing);
    expect_same(fresh, {r.accumulation, r.flow, r.wetness}, {"out", "flow", "wetness"});
    expect_same(shared, {r.accumulation, r.flow, r.wetness}, {"out", "flow", "wetness"});
    EXPECT_LT(sharing, filling);  // the fill's rounds skipped
    // Other heights in one tile's interior (the last tile's middle sample): every tile fills again.
    Terrain other = t;
    other.z[other.z.size() - static_cast<std::size_t>(t.size.x) * 2 - 2] -= 3.0f;
    Heightfield other_ground = test::heights_of(other);
    const AccumulationResult o = flow_accumulation(other_ground, nullptr, p);
    forget_filled_surfaces();
    test::run_across_tiles(*direction, t, counts);
    const auto refilled = test::run_across_tiles(*accumulation, other, counts, 2, &again);
    expect_same(refilled, {o.accumulation, o.flow, o.wetness}, {"out", "flow", "wetness"});
    EXPECT_GT(again, sharing);
  }
  forget_filled_surfaces();
  const TileRect rect{{0, 0}, {2, 2}};
  const HeightsHash h = hash_heights(std::vector<float>{1, 2, 3, 4});
  EXPECT_FALSE(h == hash_heights(std::vector<float>{1, 2, 4, 3}));
  keep_filled_surface(rect, {5, 5}, h, {1, 2, 3, 4});
  EXPECT_NE(find_filled_surface(rect, {5, 5}, h), nullptr);
  EXPECT_EQ(find_filled_surface(rect, {5, 6}, h), nullptr);  // another domain
  EXPECT_EQ(find_filled_surface(rect, {5, 5}, hash_heights(std::vector<float>{1, 2, 3, 5})), nullptr);
  forget_filled_surfaces();
}

TEST(FlowAcrossTiles, RingsComeFromTheTilesAroundAsCheckedBytes) {
  // A 9 x 7 domain in 2 x 2 tiles sharing column 4 and row 3; every value is its sample's index.
  const glm::ivec2 domain(9, 7);
  const std::vector<TileRect> rects = {{{0, 0}, {5, 4}}, {{4, 0}, {5, 4}}, {{0, 3}, {5, 4}}, {{4, 3}, {5, 4}}};
  auto values_of = [&](const TileRect& r) {
    std::vector<float> v;
    for (int j = 0; j < r.size.y; ++j)
      for (int i = 0; i < r.size.x; ++i) v.push_back(static_cast<float>((r.first.y + j) * domain.x + r.first.x + i));
    return v;
  };
  std::vector<std::string> messages;
  for (const auto& r : rects) messages.push_back(ring_message(values_of(r), r));
  const auto answers = solve_rings(message_views(messages), domain);
  for (std::size_t t = 0; t < rects.size(); ++t) {
    const TileRect ringed = ringed_rect(rects[t], domain);
    const auto z = with_ring(values_of(rects[t]), rects[t], domain, answers[t]);
    ASSERT_EQ(z.size(), static_cast<std::size_t>(ringed.size.x * ringed.size.y));
    for (int j = 0; j < ringed.size.y; ++j)
      for (int i = 0; i < ringed.size.x; ++i)
        EXPECT_EQ(z[static_cast<std::size_t>(j * ringed.size.x + i)],
                  static_cast<float>((ringed.first.y + j) * domain.x + ringed.first.x + i));
  }
  EXPECT_EQ(ringed_rect(rects[3], domain).first, glm::ivec2(3, 2));
  EXPECT_EQ(ringed_rect(rects[3], domain).size, glm::ivec2(6, 5));  // clipped at the domain's border
  // Malformed bytes, tiles that disagree on a shared sample, a ring no tile holds, answers of the wrong length.
  EXPECT_THROW(solve_rings(message_views({messages[0] + "x"}), domain), std::invalid_argument);
  EXPECT_THROW(solve_rings(message_views({messages[0].substr(0, messages[0].size() - 1)}), domain),
               std::invalid_argument);
  EXPECT_THROW(solve_rings(message_views({messages[0]}), {4, 4}), std::invalid_argument);  // outside the domain
  EXPECT_THROW(solve_rings(message_views({messages[0]}), domain), std::invalid_argument);  // nothing around tile 0
  auto other = values_of(rects[1]);
  other[0] += 1.0f;  // its shared corner with tile 0
  EXPECT_THROW(
      solve_rings(message_views({messages[0], ring_message(other, rects[1]), messages[2], messages[3]}), domain),
      std::invalid_argument);
  std::string short_answer;
  bytes::put_vector(short_answer, std::vector<float>(3, 0.0f));
  EXPECT_THROW(with_ring(values_of(rects[0]), rects[0], domain, short_answer), std::invalid_argument);
  EXPECT_THROW(with_ring(values_of(rects[0]), rects[0], domain, answers[0] + "x"), std::invalid_argument);
  // Two fields in one round: each comes back with its own ring (the second field is the first negated).
  auto negated = [&](const TileRect& r) {
    auto v = values_of(r);
    for (float& x : v) x = -x;
    return v;
  };
  std::vector<std::string> pairs;
  for (const auto& r : rects) pairs.push_back(ring_pair_message(values_of(r), negated(r), r));
  const auto pair_answers = solve_ring_pairs(message_views(pairs), domain);
  for (std::size_t t = 0; t < rects.size(); ++t) {
    const auto [first, second] =
        with_ring_pair(values_of(rects[t]), negated(rects[t]), rects[t], domain, pair_answers[t]);
    EXPECT_EQ(first, with_ring(values_of(rects[t]), rects[t], domain, answers[t]));
    ASSERT_EQ(second.size(), first.size());
    for (std::size_t k = 0; k < first.size(); ++k) EXPECT_EQ(second[k], -first[k]);
  }
  EXPECT_THROW(solve_ring_pairs(message_views({pairs[0].substr(0, pairs[0].size() - 1)}), domain),
               std::invalid_argument);
  EXPECT_THROW(solve_ring_pairs(message_views({pairs[0] + "x"}), domain), std::invalid_argument);
  EXPECT_THROW(with_ring_pair(values_of(rects[0]), negated(rects[0]), rects[0], domain, pair_answers[0] + "x"),
               std::invalid_argument);
}

}  // namespace
}  // namespace orogen::hydrology
