// FlowDirection (fill on), FlowAccumulation (D8) and Watersheds across tiles through their registered tile-graph
// algorithms (nodes/hydrology/flow_across_tiles.cpp): the epsilon fill's rounds, a one-sample ring of the filled
// surface from the tiles around, D8 counts through perimeter links (Barnes 2017), the largest count for the flow map,
// and basin labels through the same links with the cells of each basin added up across tiles. Put together, the tiles'
// outputs must equal the whole-domain functions the nodes call bit for bit, on every tiling, on terrains whose lakes,
// flats and drainage cross tile borders and corners; and the accumulation at every outlet is the area that drains to
// it.
#include <map>
#include <set>

#include <gtest/gtest.h>

#include "graph/tile_bytes.h"
#include "nodes/hydrology/flow.h"
#include "nodes/hydrology/tile_basins.h"
#include "nodes/hydrology/tile_ring.h"
#include "support/tile_graph_run.h"

namespace orogen::hydrology {
namespace {

using test::algorithm_of;
using test::domain_of;
using test::same_bits;
using test::Terrain;
using test::terrain;

// The last: tiles of two samples on the 41 x 33 terrain (a neighbour's ring is its whole tile).
const std::vector<glm::ivec2> kTilings = {{1, 1}, {2, 2}, {3, 2}, {4, 3}, {1, 4}, {7, 6}, {40, 32}};

std::string tiling_text(glm::ivec2 size, int levels, glm::ivec2 counts) {
  return std::to_string(size.x) + "x" + std::to_string(size.y) + " levels " + std::to_string(levels) + " tiles " +
         std::to_string(counts.x) + "x" + std::to_string(counts.y);
}

void expect_same(const std::vector<std::vector<float>>& tiled, const std::vector<HeightfieldPtr>& whole,
                 const std::vector<const char*>& names) {
  ASSERT_EQ(tiled.size(), whole.size());
  for (std::size_t o = 0; o < whole.size(); ++o) {
    ASSERT_TRUE(whole[o]) << names[o];
    EXPECT_TRUE(same_bits(tiled[o], whole[o]->data)) << names[o];
  }
}

// The lowest-numbered tile of `counts` holding sample (i, j) of a domain of `size` samples.
int tile_of(int i, int j, glm::ivec2 size, glm::ivec2 counts) {
  auto index = [](int s, int samples, int tiles) {
    int t = 0;
    while (t + 1 < tiles && test::edge(t + 1, samples, tiles) < s) ++t;
    return t;
  };
  return index(j, size.y, counts.y) * counts.x + index(i, size.x, counts.x);
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
        for (const glm::ivec2 counts : kTilings) {
          SCOPED_TRACE(tiling_text(size, levels, counts));
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
          for (const glm::ivec2 counts : kTilings) {
            SCOPED_TRACE(tiling_text(size, levels, counts));
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
                crossed.insert(tile_of(g.column(x), g.row(x), size, counts));
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
          for (const glm::ivec2 counts : kTilings) {
            SCOPED_TRACE(tiling_text(size, levels, counts));
            const auto tiled = test::run_across_tiles(*algorithm, t, counts);
            expect_same(tiled, {r.id, r.area}, {"out", "area"});
            if (counts.x * counts.y < 4) continue;
            std::map<int, std::set<int>> tiles_of;
            for (int j = 0; j < size.y; ++j)
              for (int i = 0; i < size.x; ++i)
                if (const int id = static_cast<int>(r.id->data[static_cast<std::size_t>(j * size.x + i)]); id > 0)
                  tiles_of[id].insert(tile_of(i, j, size, counts));
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
  const auto answers = solve_basin_links({links}, {3, 3});
  EXPECT_THROW(solve_basin_links({links + "x"}, {3, 3}), std::invalid_argument);
  EXPECT_THROW(solve_basin_links({links.substr(0, links.size() - 1)}, {3, 3}), std::invalid_argument);
  EXPECT_THROW(solve_basin_links({links}, {2, 3}), std::invalid_argument);
  EXPECT_THROW(solve_basin_links({links, links}, {3, 3}), std::invalid_argument);  // one edge taken twice
  EXPECT_THROW(take_basin_outlets(basins, answers[0] + "x"), std::invalid_argument);
  take_basin_outlets(basins, answers[0]);
  EXPECT_EQ(basins.outlet[4], 5);
  EXPECT_EQ(basins.outlet[3], 5);
  const std::string counts = basin_count_message(basins);
  const auto numbers = solve_basin_counts({counts}, 1.0, 0.0);
  EXPECT_THROW(solve_basin_counts({counts + "x"}, 1.0, 0.0), std::invalid_argument);
  std::vector<float> id(9), area(9);
  EXPECT_THROW(basin_maps(basins, numbers[0] + "x", 1.0, id, area), std::invalid_argument);
  basin_maps(basins, numbers[0], 1.0, id, area);
  EXPECT_EQ(id[4], 1.0f);  // the largest basin: the outlet east of the centre, with three cells
  EXPECT_EQ(area[4], 3.0f);
  EXPECT_EQ(id[0], 2.0f);  // then the one-cell basins by outlet index
  EXPECT_EQ(area[0], 1.0f);
}

TEST(FlowAcrossTiles, WeightedAndDispersiveAccumulationStayOnTheWholeDomain) {
  const Domain whole = Domain::from_extent({0, 0}, {640, 640}, {65, 65});
  EXPECT_NE(algorithm_of("FlowAccumulation", {{"method", std::string("d8")}}, whole), nullptr);
  EXPECT_NE(algorithm_of("FlowAccumulation", {{"method", std::string("d8")}, {"fill", false}}, whole), nullptr);
  EXPECT_EQ(algorithm_of("FlowAccumulation", {{"method", std::string("mfd")}}, whole), nullptr);
  EXPECT_EQ(algorithm_of("FlowAccumulation", {{"method", std::string("dinf")}}, whole), nullptr);
  EXPECT_NE(algorithm_of("FlowDirection", {{"method", std::string("mfd")}}, whole), nullptr);
  EXPECT_EQ(algorithm_of("FlowDirection", {{"fill", false}}, whole), nullptr);  // a local node then
  // A linked rainfall weight keeps the node on the whole domain (cli/tiling.h), and the algorithm refuses one.
  EXPECT_EQ(tile_graph_unlinked_inputs("FlowAccumulation"), std::vector<std::string>{"rainfall_weight"});
  EXPECT_TRUE(tile_graph_unlinked_inputs("FlowDirection").empty());
  EXPECT_NE(algorithm_of("Watersheds", {{"fill", false}}, whole), nullptr);
  const auto algorithm = algorithm_of("FlowAccumulation", {{"method", std::string("d8")}}, whole);
  auto h = std::make_shared<Heightfield>(whole);
  EXPECT_THROW(algorithm->start({HeightfieldPtr(h), HeightfieldPtr(h)}), std::invalid_argument);
  EXPECT_NO_THROW(algorithm->start({HeightfieldPtr(h), PortValue{}}));
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
  const auto answers = solve_rings(messages, domain);
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
  EXPECT_THROW(solve_rings({messages[0] + "x"}, domain), std::invalid_argument);
  EXPECT_THROW(solve_rings({messages[0].substr(0, messages[0].size() - 1)}, domain), std::invalid_argument);
  EXPECT_THROW(solve_rings({messages[0]}, {4, 4}), std::invalid_argument);  // outside the domain
  EXPECT_THROW(solve_rings({messages[0]}, domain), std::invalid_argument);  // nothing around tile 0
  auto other = values_of(rects[1]);
  other[0] += 1.0f;  // its shared corner with tile 0
  EXPECT_THROW(solve_rings({messages[0], ring_message(other, rects[1]), messages[2], messages[3]}, domain),
               std::invalid_argument);
  std::string short_answer;
  bytes::put_vector(short_answer, std::vector<float>(3, 0.0f));
  EXPECT_THROW(with_ring(values_of(rects[0]), rects[0], domain, short_answer), std::invalid_argument);
  EXPECT_THROW(with_ring(values_of(rects[0]), rects[0], domain, answers[0] + "x"), std::invalid_argument);
}

}  // namespace
}  // namespace orogen::hydrology
