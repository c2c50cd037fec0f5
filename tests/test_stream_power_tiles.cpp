// StreamPower across tiles (nodes/erosion/stream_power_across_tiles.cpp): with depressions 'priority_flood' every step
// (uplift, diffusion sub-steps with their halos, the float fill where a tile has a pit, D8 routing with the ring, the
// counts through perimeter links, the implicit incision along chains that cross tiles) runs on the tiles; put
// together, the five maps must equal the whole-domain run bit for bit on every tiling (tiles of 2 samples included),
// for n = 1 and n != 1, with a channel threshold, a mask and an uplift field. A run that skips one exchange must not.
#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <utility>
#include <vector>
#include <random>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "graph/distribution.h"
#include "graph/node_type.h"
#include "graph/registry.h"
#include "graph/tile_graph.h"
#include "nodes/erosion/stream_power.h"
#include "nodes/erosion/stream_power_across_tiles.h"
#include "support/tile_graph_run.h"

namespace orogen::erosion {
namespace {

using test::same_bits;

// Rough terrain with closed depressions across tile borders and corners (test::terrain), 20 times taller, an
// uplift field (0 to 2) and a mask (clamped to 0..1 by the node).
struct Fields {
  test::Terrain terrain;
  std::vector<float> mask, uplift;
};

Fields fields(glm::ivec2 size, unsigned seed) {
  Fields f{test::terrain(size, seed, 0), {}, {}};
  for (float& z : f.terrain.z) z = 200.0f + 20.0f * z;
  std::mt19937 rng(seed + 1);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (std::size_t k = 0; k < f.terrain.z.size(); ++k) {
    f.mask.push_back(1.4f * u(rng) - 0.2f);
    f.uplift.push_back(2.0f * u(rng));
  }
  return f;
}

StreamPowerParams params(double n, double channel_area) {
  StreamPowerParams p;
  p.k = 2e-4;
  p.m = 0.45;
  p.n = n;
  p.uplift = 2e-3;
  p.diffusion = 0.1;  // 5 diffusion sub-steps per step on 10 m cells
  p.dt = 1000.0;
  p.duration = 8000.0;
  p.sea_level = -1e4;
  p.channel_area = channel_area;
  p.depressions = StreamPowerParams::Depressions::PriorityFlood;
  return p;
}

std::map<std::string, ParamValue> node_params(const StreamPowerParams& p) {
  return {{"k", p.k},
          {"m", p.m},
          {"n", p.n},
          {"uplift_rate", p.uplift},
          {"diffusion", p.diffusion},
          {"time_step", p.dt},
          {"duration", p.duration},
          {"sea_level", p.sea_level},
          {"channel_area", p.channel_area},
          {"depressions", std::string("priority_flood")}};
}

// out, erosion, deposition, flow, accumulation.
std::vector<std::vector<float>> whole_domain(const Fields& f, const StreamPowerParams& p, bool mask, bool uplift) {
  const Heightfield in = test::heights_of(f.terrain);
  Heightfield m(in.domain), u(in.domain);
  m.data = f.mask, u.data = f.uplift;
  std::shared_ptr<Heightfield> acc;
  const ErosionMaps maps =
      stream_power(in, p, uplift ? &u : nullptr, mask ? &m : nullptr, nullptr, nullptr, nullptr, &acc);
  return {maps.out->data, maps.erosion->data, maps.deposition->data, maps.flow->data, acc->data};
}

std::vector<std::vector<float>> across_tiles(const TileGraphAlgorithm& algorithm, const Fields& f, glm::ivec2 counts,
                                             bool mask, bool uplift, int* rounds = nullptr) {
  return test::run_across_tiles(algorithm, f.terrain, counts, 3, rounds,
                                {mask ? &f.mask : nullptr, uplift ? &f.uplift : nullptr});
}

void expect_same(const std::vector<std::vector<float>>& tiled, const std::vector<std::vector<float>>& whole) {
  const char* names[] = {"out", "erosion", "deposition", "flow", "accumulation"};
  ASSERT_EQ(tiled.size(), 5u);
  for (std::size_t o = 0; o < 5; ++o) EXPECT_TRUE(same_bits(tiled[o], whole[o])) << names[o];
}

// The registered algorithm, and ones that always fill across the tiles (no pit basin gathered) and always gather.
std::vector<std::pair<std::string, std::unique_ptr<TileGraphAlgorithm>>> algorithms(const StreamPowerParams& p,
                                                                                    const Domain& whole) {
  std::vector<std::pair<std::string, std::unique_ptr<TileGraphAlgorithm>>> all;
  all.emplace_back("registered", test::algorithm_of("StreamPower", node_params(p), whole));
  all.emplace_back("fill across tiles", stream_power_across_tiles(p, whole, 0));
  all.emplace_back("basins gathered", stream_power_across_tiles(p, whole, std::size_t{1} << 40));
  return all;
}

TEST(StreamPowerAcrossTiles, EveryTilingEqualsTheWholeDomainRunBitForBit) {
  const Fields f = fields({61, 47}, 7);
  const Domain whole = test::domain_of(f.terrain);
  for (const double n : {1.0, 1.5})
    for (const double channel_area : {0.0, 2000.0}) {
      const StreamPowerParams p = params(n, channel_area);
      for (const auto& [name, algorithm] : algorithms(p, whole)) {
        ASSERT_TRUE(algorithm);
        for (const bool linked : {false, true}) {
          const auto expected = whole_domain(f, p, linked, linked);
          ASSERT_FALSE(same_bits(expected[0], f.terrain.z)) << "the run must change the terrain";
          for (const glm::ivec2 counts : {glm::ivec2(1, 1), glm::ivec2(2, 2), glm::ivec2(3, 2), glm::ivec2(4, 3),
                                          glm::ivec2(1, 4), glm::ivec2(7, 6)}) {
            SCOPED_TRACE(name + ", n " + std::to_string(n) + " channel area " + std::to_string(channel_area) +
                         " fields " + std::to_string(linked) + " tiles " + test::tiles_text(counts));
            expect_same(across_tiles(*algorithm, f, counts, linked, linked), expected);
          }
        }
      }
    }
}

// Tiles of 2 and 3 samples: every chain of receivers crosses many tiles, every cell is near a border.
TEST(StreamPowerAcrossTiles, TilesOfTwoSamplesEqualTheWholeDomainRun) {
  const Fields f = fields({31, 25}, 8);
  const StreamPowerParams p = params(1.0, 0.0);
  const auto expected = whole_domain(f, p, true, true);
  for (const auto& [name, algorithm] : algorithms(p, test::domain_of(f.terrain)))
    for (const glm::ivec2 counts : {glm::ivec2(30, 1), glm::ivec2(15, 12), glm::ivec2(10, 24)}) {
      SCOPED_TRACE(name + ", tiles " + test::tiles_text(counts));
      expect_same(across_tiles(*algorithm, f, counts, true, true), expected);
    }
}

// The fill runs only in the steps that find a pit: the first step of the random terrain fills its closed depressions
// across the tiles (its pit basins cover most of it), later steps of the drained surface find none, or a few small
// basins that are gathered and filled in one piece. Counted from the messages' phase tags
// (stream_power_across_tiles.cpp's Phase: 2 the pit basins' links, 5 the spill graphs of a fill across the tiles).
TEST(StreamPowerAcrossTiles, StepsWithoutPitsSkipTheFillAndSmallBasinsAreGathered) {
  const Fields f = fields({121, 97}, 7);
  StreamPowerParams p = params(1.0, 0.0);
  p.diffusion = 0.0;  // diffusion raises channel floors into new pits every step
  p.duration = 20 * p.dt;
  const auto algorithm = stream_power_across_tiles(p, test::domain_of(f.terrain));
  auto tiles = test::start_tiles(*algorithm, f.terrain, {3, 2}, 3);
  int with_pits = 0, across = 0;
  for (int round = 0;; ++round) {
    std::vector<std::string> messages;
    for (auto& tile : tiles) messages.push_back(tile->message(round));
    with_pits += messages[0][0] == 2;
    across += messages[0][0] == 5;
    const auto answers = algorithm->solve(round, messages);
    for (std::size_t k = 0; k < tiles.size(); ++k) tiles[k]->answer(round, answers[k]);
    if (!algorithm->another_round(round, messages)) break;
  }
  EXPECT_GE(across, 1) << "the first step fills the terrain's pits across the tiles";
  EXPECT_LT(across, with_pits) << "later steps' small pit basins are gathered";
  EXPECT_LE(with_pits, 8) << "once drained, steps find no pit (21: every step and the end)";
}

// The mutation check: one tile missing one halo or one incision answer changes the result (or stops the run).
TEST(StreamPowerAcrossTiles, SkippingOneExchangeBreaksTheEquality) {
  const Fields f = fields({61, 47}, 7);
  const StreamPowerParams p = params(1.0, 0.0);
  const auto algorithm = stream_power_across_tiles(p, test::domain_of(f.terrain));
  const auto expected = whole_domain(f, p, false, false);
  expect_same(across_tiles(*algorithm, f, {3, 2}, false, false), expected);
  for (const int round : {2, 40}) {
    SCOPED_TRACE("skipped round " + std::to_string(round));
    auto tiles = test::start_tiles(*algorithm, f.terrain, {3, 2}, 3);
    bool differs = false;
    try {
      test::run_rounds(*algorithm, tiles, test::dropping([&](std::size_t t, int r) { return t == 4 && r == round; }));
      const auto joined = tiles[4]->outputs();
      const auto& out = std::get<HeightfieldPtr>(joined[0])->data;
      std::vector<float> cut;
      const auto& d = std::get<HeightfieldPtr>(joined[0])->domain;
      for (int j = 0; j < d.height(); ++j)
        for (int i = 0; i < d.width(); ++i)
          cut.push_back(expected[0][static_cast<std::size_t>(d.first.y + j) * 61 + d.first.x + i]);
      differs = !same_bits(out, cut);
    } catch (const std::exception&) {
      differs = true;  // the tiles fell out of step
    }
    EXPECT_TRUE(differs);
  }
}

// Cells below sea level are base level, step by step (the uplift lifts some of the sea floor into land during the
// run): the tiles route, fill and incise with the same base level as the whole-domain run.
TEST(StreamPowerAcrossTiles, CellsBelowSeaLevelAreBaseLevelAsOnTheWholeDomain) {
  const Fields f = fields({61, 47}, 9);
  std::vector<float> sorted = f.terrain.z;
  std::sort(sorted.begin(), sorted.end());
  StreamPowerParams p = params(1.0, 0.0);
  p.sea_level = sorted[sorted.size() / 5] + 8.0;  // a fifth of the cells and more; the uplift raises 16 m
  const Domain whole = test::domain_of(f.terrain);
  for (const bool linked : {false, true}) {
    const auto expected = whole_domain(f, p, linked, linked);
    std::size_t sea = 0, risen = 0;
    for (std::size_t k = 0; k < f.terrain.z.size(); ++k) {
      sea += f.terrain.z[k] < p.sea_level;
      risen += f.terrain.z[k] < p.sea_level && expected[0][k] >= p.sea_level;
    }
    ASSERT_GT(sea, f.terrain.z.size() / 5);
    if (!linked) {
      ASSERT_GT(risen, 10u) << "some sea floor must rise into land";
    }
    for (const auto& [name, algorithm] : algorithms(p, whole))
      for (const glm::ivec2 counts : {glm::ivec2(2, 2), glm::ivec2(3, 2), glm::ivec2(7, 6), glm::ivec2(15, 12)}) {
        SCOPED_TRACE(name + ", fields " + std::to_string(linked) + ", tiles " + test::tiles_text(counts));
        expect_same(across_tiles(*algorithm, f, counts, linked, linked), expected);
      }
  }
}

// Damaged bytes are refused in every phase: a message one byte short (the solve throws) and an answer one byte short
// (the tile throws), checked on the first round of each phase of a run that fills across the tiles and gathers.
TEST(StreamPowerAcrossTiles, DamagedMessagesAndAnswersAreRefusedInEveryPhase) {
  const Fields f = fields({61, 47}, 7);
  StreamPowerParams p = params(1.0, 0.0);
  p.duration = 3 * p.dt;
  for (const std::size_t limit : {std::size_t{0}, std::size_t{1} << 40}) {
    const auto algorithm = stream_power_across_tiles(p, test::domain_of(f.terrain), limit);
    auto tiles = test::start_tiles(*algorithm, f.terrain, {3, 2}, 3);
    std::set<char> checked;
    for (int round = 0;; ++round) {
      std::vector<std::string> messages;
      for (auto& tile : tiles) messages.push_back(tile->message(round));
      const char phase = messages[0][0];
      if (checked.insert(phase).second) {
        SCOPED_TRACE("limit " + std::to_string(limit) + ", phase " + std::to_string(phase));
        test::expect_damaged_bytes_refused(*algorithm, tiles, round, messages, false);
      }
      const auto answers = algorithm->solve(round, messages);
      for (std::size_t k = 0; k < tiles.size(); ++k) tiles[k]->answer(round, answers[k]);
      if (!algorithm->another_round(round, messages)) break;
    }
    EXPECT_GE(checked.size(), limit == 0 ? 10u : 8u) << "the run must go through the phases";
  }
}

// The node is a tile-graph node with the Priority-Flood fill and computed whole with the basin graph.
TEST(StreamPowerAcrossTiles, DistributionFollowsTheDepressionsParameter) {
  const NodeType& type = *NodeRegistry::instance().find("StreamPower");
  const Domain whole = Domain::from_extent({0, 0}, {100, 100}, {11, 11});
  auto values = test::params_of(type, {});
  EXPECT_EQ(type.distribution_for(values), Distribution::Gathered);
  EXPECT_EQ(test::algorithm_of("StreamPower", {}, whole), nullptr);
  values = test::params_of(type, {{"depressions", std::string("priority_flood")}});
  EXPECT_EQ(type.distribution_for(values), Distribution::TileGraph);
  EXPECT_NE(test::algorithm_of("StreamPower", {{"depressions", std::string("priority_flood")}}, whole), nullptr);
}

}  // namespace
}  // namespace orogen::erosion
