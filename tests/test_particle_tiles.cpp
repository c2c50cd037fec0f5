// HydraulicErosion across tiles (nodes/erosion/particles_across_tiles.cpp): the whole-domain run's droplet schedule,
// each block run by one tile, the samples a phase changed sent to the tiles that hold them. Put together, the tiles
// must equal the whole-domain node bit for bit (heights, change maps, flow map and report) on every tiling, tiles of
// 2 samples included, with a mask linked or not; a run that skips one exchange must not.
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <random>

#include <gtest/gtest.h>

#include "evaluator/run_node.h"
#include "graph/domain.h"
#include "graph/node_type.h"
#include "graph/registry.h"
#include "graph/report.h"
#include "graph/tile_graph.h"
#include "nodes/erosion/droplet_schedule.h"
#include "nodes/erosion/particles_across_tiles.h"
#include "support/tile_graph_run.h"

namespace orogen::erosion {
namespace {

using test::same_bits;

struct Fields {
  Domain domain;
  HeightfieldPtr in, mask;
};

// Ridges and valleys with noise (droplets run far and cross tiles) and a mask, 10 m between samples.
Fields fields(glm::ivec2 size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Fields f;
  f.domain = Domain::from_extent({0, 0}, {10.0 * (size.x - 1), 10.0 * (size.y - 1)}, size);
  auto in = std::make_shared<Heightfield>(f.domain), mask = std::make_shared<Heightfield>(f.domain);
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i) {
      in->at(i, j) =
          60.0f * std::sin(0.11f * i) * std::cos(0.07f * j) + 0.4f * static_cast<float>(i + j) + 3.0f * u(rng);
      mask->at(i, j) = 1.4f * u(rng) - 0.2f;  // clamped to 0..1 by the node
    }
  f.in = in, f.mask = mask;
  return f;
}

// Short droplets and a narrow brush, so the schedule has blocks of 32 samples (several per tile of 129^2), and about
// 8600 droplets in 3 rounds of 4096.
const std::map<std::string, ParamValue> kParams = {
    {"droplets_per_km2", 6000.0}, {"lifetime", 60.0}, {"step_length", 10.0}, {"radius", 15.0}, {"erosion", 0.5},
    {"seed", std::uint64_t{7}}};

struct Maps {
  std::vector<std::vector<float>> rasters;  // out, erosion, deposition, flow
  std::string report;
};

std::unique_ptr<TileGraphAlgorithm> algorithm_of(const std::map<std::string, ParamValue>& set, const Domain& whole) {
  return test::algorithm_of("HydraulicErosion", set, whole);
}

Maps whole_domain(const Fields& f, bool mask) {
  std::map<std::string, PortValue> inputs{{"in", PortValue(f.in)}};
  if (mask) inputs["mask"] = PortValue(f.mask);
  const NodeRun r = run_node("HydraulicErosion", f.domain, kParams, inputs);
  Maps m;
  for (std::size_t o = 0; o < 4; ++o) m.rasters.push_back(r.get<Heightfield>(o)->data);
  m.report = r.get<Report>(4)->json;
  return m;
}

// The tiles' rounds as the driver runs them (messages through their bytes); `skip(tile, round)` drops that tile's
// answer of that round (an exchange left out: the mutation). `disagreements` counts the shared samples on which two
// tiles differ (none in a correct run).
Maps across_tiles(const TileGraphAlgorithm& algorithm, const Fields& f, glm::ivec2 counts, bool mask,
                  int* rounds_run = nullptr, const std::function<bool(std::size_t, int)>& skip = {},
                  int* disagreements = nullptr) {
  const glm::ivec2 size = f.domain.resolution;
  auto tiles = test::start_tiles(algorithm, f.domain, counts, {f.in, mask ? f.mask : nullptr});
  const int rounds = test::run_rounds(algorithm, tiles, test::dropping(skip));
  if (rounds_run) *rounds_run = rounds;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Maps joined;
  joined.rasters.assign(4, std::vector<float>(f.in->data.size(), nan));
  for (auto& tile : tiles) {
    const auto outputs = tile->outputs();
    const std::string report = std::get<ReportPtr>(outputs[4])->json;
    if (joined.report.empty()) joined.report = report;
    if (report != joined.report) {
      if (disagreements)
        ++*disagreements;
      else
        ADD_FAILURE() << "tiles disagree on the report";
    }
    for (std::size_t o = 0; o < 4; ++o) {
      const Heightfield& h = *std::get<HeightfieldPtr>(outputs[o]);
      test::join_tile_map(joined.rasters[o], h, size.x, disagreements);
    }
  }
  return joined;
}

void expect_same(const Maps& tiled, const Maps& whole) {
  const char* names[] = {"out", "erosion", "deposition", "flow"};
  for (std::size_t o = 0; o < 4; ++o) EXPECT_TRUE(same_bits(tiled.rasters[o], whole.rasters[o])) << names[o];
  EXPECT_EQ(tiled.report, whole.report);
}

TEST(ParticlesAcrossTiles, TheScheduleHasSeveralBlocksAndRoundsAtTheseSizes) {
  const Fields f = fields({129, 113}, 1);
  const auto algorithm = algorithm_of(kParams, f.domain);
  ASSERT_TRUE(algorithm);
  ParticleParams p;
  p.droplets_per_km2 = 6000.0, p.lifetime = 60.0, p.radius = 15.0;
  const DropletSchedule schedule(p, f.domain);
  EXPECT_EQ(schedule.blocks(), glm::ivec2(5, 4));
  EXPECT_EQ(schedule.rounds(), 3u);
  // Rectangles, first values, 3 rounds of 4 colors, totals and visits, the most visits.
  EXPECT_EQ(algorithm->rounds(), 2 + 12 + 2);
}

TEST(ParticlesAcrossTiles, EveryTilingEqualsTheWholeDomainNodeBitForBit) {
  const Fields f = fields({129, 113}, 1);
  const auto algorithm = algorithm_of(kParams, f.domain);
  ASSERT_TRUE(algorithm);
  for (const bool mask : {false, true}) {
    const Maps whole = whole_domain(f, mask);
    ASSERT_FALSE(same_bits(whole.rasters[0], f.in->data)) << "the droplets must erode";
    for (const glm::ivec2 counts :
         {glm::ivec2(1, 1), glm::ivec2(2, 2), glm::ivec2(3, 2), glm::ivec2(4, 3), glm::ivec2(1, 4), glm::ivec2(7, 6)}) {
      SCOPED_TRACE("mask " + std::to_string(mask) + ", tiles " + test::tiles_text(counts));
      int rounds = 0;
      expect_same(across_tiles(*algorithm, f, counts, mask, &rounds), whole);
      EXPECT_EQ(rounds, algorithm->rounds());
    }
  }
}

// Tiles of 2 and 3 samples, far narrower than a droplet's reach (10 samples) or a block (32): a block's droplets run
// on the tile holding its center, with heights from many tiles around it. 64 x 1 tiles over 65 samples are 2 samples
// wide; 32 x 24 over 65 x 49 are 3 x 3.
TEST(ParticlesAcrossTiles, TilesNarrowerThanADropletsReachWork) {
  const Fields f = fields({65, 49}, 2);
  const auto algorithm = algorithm_of(kParams, f.domain);
  const Maps whole = whole_domain(f, true);
  for (const glm::ivec2 counts : {glm::ivec2(64, 1), glm::ivec2(3, 48), glm::ivec2(32, 24), glm::ivec2(21, 16)}) {
    SCOPED_TRACE("tiles " + test::tiles_text(counts));
    expect_same(across_tiles(*algorithm, f, counts, true), whole);
  }
}

// Other brush shapes (rows of 12 and 16 weights, padding on the right), non-square cells and droplets that run for
// many steps: the margins around each block hold every sample its droplets touch.
TEST(ParticlesAcrossTiles, BrushShapesAndNonSquareCells) {
  Fields f = fields({97, 81}, 4);
  const Domain d = Domain::from_extent({0, 0}, {960.0, 1600.0}, {97, 81});  // 10 m x 20 m cells
  auto in = std::make_shared<Heightfield>(*f.in), mask = std::make_shared<Heightfield>(*f.mask);
  in->domain = d, mask->domain = d;
  f.domain = d, f.in = in, f.mask = mask;
  for (const double radius : {40.0, 65.0}) {
    auto params = kParams;
    params["radius"] = radius, params["lifetime"] = 150.0, params["step_length"] = 7.0, params["inertia"] = 0.3;
    const auto algorithm = algorithm_of(params, f.domain);
    const NodeRun r =
        run_node("HydraulicErosion", f.domain, params, {{"in", PortValue(f.in)}, {"mask", PortValue(f.mask)}});
    Maps whole;
    for (std::size_t o = 0; o < 4; ++o) whole.rasters.push_back(r.get<Heightfield>(o)->data);
    whole.report = r.get<Report>(4)->json;
    for (const glm::ivec2 counts : {glm::ivec2(3, 2), glm::ivec2(7, 6), glm::ivec2(24, 20)}) {
      SCOPED_TRACE("radius " + std::to_string(radius) + ", tiles " + test::tiles_text(counts));
      expect_same(across_tiles(*algorithm, f, counts, true), whole);
    }
  }
}

// A whole-domain schedule of one block (a reach wider than half the domain) and no droplets at all.
TEST(ParticlesAcrossTiles, OneBlockAndNoDropletsToo) {
  const Fields f = fields({65, 65}, 3);
  for (const double lifetime : {60.0, 400.0}) {
    for (const double density : {0.0, 3000.0}) {
      auto params = kParams;
      params["lifetime"] = lifetime, params["droplets_per_km2"] = density;
      const auto algorithm = algorithm_of(params, f.domain);
      std::map<std::string, PortValue> inputs{{"in", PortValue(f.in)}};
      const NodeRun r = run_node("HydraulicErosion", f.domain, params, inputs);
      Maps whole;
      for (std::size_t o = 0; o < 4; ++o) whole.rasters.push_back(r.get<Heightfield>(o)->data);
      whole.report = r.get<Report>(4)->json;
      for (const glm::ivec2 counts : {glm::ivec2(1, 1), glm::ivec2(3, 2)}) {
        SCOPED_TRACE("lifetime " + std::to_string(lifetime) + ", density " + std::to_string(density) + ", tiles " +
                     test::tiles_text(counts));
        expect_same(across_tiles(*algorithm, f, counts, false), whole);
      }
    }
  }
}

// A dense run on a tiny grid still runs across the tiles; only droplet phases beyond what rounds of all-gathers are
// worth (the same density over 4096 km^2) give no algorithm, so the node stays on the whole domain, exact either way.
TEST(ParticlesAcrossTiles, OnlyPhasesBeyondWhatAllGathersAreWorthStayOnTheWholeDomain) {
  const Fields f = fields({65, 65}, 3);
  auto params = kParams;
  params["droplets_per_km2"] = 1e8;  // 41 M droplets in 10,000 rounds of 4096: 40,000 phases
  EXPECT_TRUE(algorithm_of(params, f.domain));
  params["step_length"] = 60.0;
  const Domain wide = Domain::from_extent({0, 0}, {64000.0, 64000.0}, {65, 65});  // 4096 km^2: 4e11 droplets
  EXPECT_FALSE(algorithm_of(params, wide));
}

// The mutation check: one tile missing one exchange (the first values, a phase's changes, the visits or the most
// visits) changes the result, so the equality above depends on every kind of exchange.
TEST(ParticlesAcrossTiles, SkippingOneExchangeBreaksTheEquality) {
  const Fields f = fields({129, 113}, 1);
  const auto algorithm = algorithm_of(kParams, f.domain);
  const Maps whole = whole_domain(f, false);
  expect_same(across_tiles(*algorithm, f, {3, 2}, false), whole);
  for (const int round : {1, 2, 5, algorithm->rounds() - 2, algorithm->rounds() - 1}) {
    SCOPED_TRACE("skipped round " + std::to_string(round));
    int disagreements = 0;
    const Maps mutated = across_tiles(
        *algorithm, f, {3, 2}, false, nullptr, [&](std::size_t tile, int r) { return tile == 4 && r == round; },
        &disagreements);
    bool differs = mutated.report != whole.report;
    for (std::size_t o = 0; o < 4; ++o) differs = differs || !same_bits(mutated.rasters[o], whole.rasters[o]);
    EXPECT_TRUE(differs);
    // The visits and the most visits (the last two rounds) are per tile: a tile that misses them disagrees with its
    // neighbors on the samples they share (an earlier exchange missed shows in the results only).
    if (round >= algorithm->rounds() - 2) {
      EXPECT_GT(disagreements, 0);
    }
  }
}

// What travels per phase is the changed samples near the tiles' borders, not the tiles; damaged bytes are refused.
TEST(ParticlesAcrossTiles, MessagesAreSmallAndTheirBytesAreChecked) {
  const Fields f = fields({129, 113}, 1);
  const auto algorithm = algorithm_of(kParams, f.domain);
  auto tiles = test::start_tiles(*algorithm, f.domain, {2, 2}, {f.in, nullptr});
  std::vector<std::string> messages;
  for (int round = 0; round < 3; ++round) {
    messages.clear();
    for (auto& tile : tiles) messages.push_back(tile->message(round));
    if (round < 2) {
      const auto answers = algorithm->solve(round, messages);
      for (std::size_t t = 0; t < tiles.size(); ++t) tiles[t]->answer(round, answers[t]);
    }
  }
  // A phase's message: well under the tile's 65 x 57 heights.
  for (const auto& m : messages) EXPECT_LT(m.size(), 65u * 57u * 4u);
  // HydraulicErosion's solve does not count the messages: a missing one is not checked here.
  test::expect_damaged_bytes_refused(*algorithm, tiles, 2, messages, false);
  auto damaged = messages;
  ASSERT_GT(damaged[3].size(), 8u);
  damaged[3][7] = '\x7f';  // the first part's target, far beyond the tiles
  EXPECT_THROW(algorithm->solve(2, damaged), std::invalid_argument);
  const auto answers = algorithm->solve(2, messages);
  EXPECT_THROW(tiles[0]->answer(2, std::string_view(answers[1])), std::invalid_argument);
}

}  // namespace
}  // namespace orogen::erosion
