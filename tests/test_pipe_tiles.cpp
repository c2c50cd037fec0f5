// PipeErosion across tiles (nodes/erosion/pipe_across_tiles.cpp): each tile steps its samples with a 2-sample halo
// exchanged every step and the time step from the deepest water over all tiles; put together, the tiles must equal
// the whole-domain run bit for bit on every tiling (tiles of 2 samples included), in uniform and Drops rain, with
// every field linked or none, over sea (sinks) and land. A run that skips one halo exchange must not.
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <random>

#include <gtest/gtest.h>

#include "graph/domain.h"
#include "graph/node_type.h"
#include "graph/registry.h"
#include "graph/tile_graph.h"
#include "nodes/erosion/pipe.h"
#include "nodes/erosion/pipe_across_tiles.h"
#include "support/tile_graph_run.h"

namespace orogen::erosion {
namespace {

using test::same_bits;

// The node's inputs in input order: in, mask, rainfall_rate, moisture, evaporation_factor, hardness.
struct Fields {
  Domain domain;
  std::vector<HeightfieldPtr> f;
};

// An island: a rough dome on 10 m samples whose rim lies under sea level 0 (sinks, and whole rows of sea), with
// random driving fields (some outside their ranges: the node clamps them).
Fields fields(glm::ivec2 size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  Fields out;
  out.domain = Domain::from_extent({0, 0}, {10.0 * (size.x - 1), 10.0 * (size.y - 1)}, size);
  for (int k = 0; k < 6; ++k) out.f.push_back(std::make_shared<Heightfield>(out.domain));
  auto field = [&](int k) { return std::const_pointer_cast<Heightfield>(out.f[static_cast<std::size_t>(k)]); };
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i) {
      const double x = (i - 0.45 * size.x) / size.x, y = (j - 0.55 * size.y) / size.y;
      field(0)->at(i, j) = static_cast<float>(60.0 * (0.16 - x * x - y * y) / 0.16) + 4.0f * u(rng);
      field(1)->at(i, j) = 1.4f * u(rng) - 0.2f;
      field(2)->at(i, j) = 3000.0f * u(rng);
      field(3)->at(i, j) = 1.3f * u(rng) - 0.1f;
      field(4)->at(i, j) = 2.0f * u(rng);
      field(5)->at(i, j) = u(rng);
    }
  return out;
}

struct Maps {
  std::vector<std::vector<float>> m;  // out, erosion, deposition, flow, water_depth, velocity
};

std::map<std::string, ParamValue> node_params(bool drops) {
  return {{"duration", 120.0},
          {"rainfall_rate", 1500.0},
          {"rain_mode", std::string(drops ? "drops" : "uniform")},
          {"drop_chance", 0.2},
          {"capacity", 4.0},
          {"sea_level", 0.0},
          {"seed", std::uint64_t{5}},
          {"layer_depth", drops ? 0.05 : 0.0}};
}

PipeParams pipe_params(const std::map<std::string, ParamValue>& set) {
  PipeParams p;
  p.duration = std::get<double>(set.at("duration"));
  p.rain_rate = std::get<double>(set.at("rainfall_rate"));
  p.rain_mode = std::get<std::string>(set.at("rain_mode")) == "drops" ? RainMode::Drops : RainMode::Uniform;
  p.drop_chance = std::get<double>(set.at("drop_chance"));
  p.capacity = std::get<double>(set.at("capacity"));
  p.sea_level = std::get<double>(set.at("sea_level"));
  p.seed = std::get<std::uint64_t>(set.at("seed"));
  p.layer_depth = std::get<double>(set.at("layer_depth"));
  return p;  // the other values are the node's defaults
}

std::unique_ptr<TileGraphAlgorithm> algorithm_of(const std::map<std::string, ParamValue>& set, const Domain& whole) {
  return test::algorithm_of("PipeErosion", set, whole);
}

// The answer of a step round without its halos (the deepest water and largest flow kept): a halo exchange left out.
std::string without_halos(std::string answer) {
  const std::size_t at = sizeof(double) + sizeof(float);
  const std::int32_t none = 0;
  std::memcpy(answer.data() + at, &none, sizeof none);
  return answer.substr(0, at + sizeof none);
}

// The tiles' rounds as the driver runs them (messages through their bytes); `stale(tile, round)` gives that tile its
// answer of that round without the halos (the mutation). `linked` says which of the five optional fields are linked.
// `disagreements` counts the shared samples on which two tiles differ (none in a correct run).
Maps across_tiles(const TileGraphAlgorithm& algorithm, const Fields& f, glm::ivec2 counts, bool linked, int* rounds_run,
                  const std::function<bool(std::size_t, int)>& stale = {}, int* disagreements = nullptr) {
  const glm::ivec2 size = f.domain.resolution;
  std::vector<HeightfieldPtr> inputs;
  for (std::size_t k = 0; k < f.f.size(); ++k) inputs.push_back(k == 0 || linked ? f.f[k] : nullptr);
  auto tiles = test::start_tiles(algorithm, f.domain, counts, inputs);
  *rounds_run = test::run_rounds(algorithm, tiles, [&](std::size_t tile, int round, std::string& answer) {
    if (stale && stale(tile, round)) answer = without_halos(answer);
    return true;
  });
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Maps joined{std::vector<std::vector<float>>(6, std::vector<float>(f.f[0]->data.size(), nan))};
  for (auto& tile : tiles) {
    const auto outputs = tile->outputs();
    for (std::size_t o = 0; o < 6; ++o) {
      const Heightfield& h = *std::get<HeightfieldPtr>(outputs[o]);
      test::join_tile_map(joined.m[o], h, size.x, disagreements);
    }
  }
  return joined;
}

Maps whole_domain(const Fields& f, const PipeParams& p, bool linked, PipeStats* stats) {
  auto g = [&](int k) { return linked ? f.f[static_cast<std::size_t>(k)].get() : nullptr; };
  const PipeMaps m = pipe_erosion(*f.f[0], p, g(1), g(2), g(3), g(4), g(5), nullptr, stats);
  return {{m.out->data, m.erosion->data, m.deposition->data, m.flow->data, m.water->data, m.velocity->data}};
}

void expect_same(const Maps& tiled, const Maps& whole) {
  const char* names[] = {"out", "erosion", "deposition", "flow", "water_depth", "velocity"};
  for (std::size_t o = 0; o < 6; ++o) EXPECT_TRUE(same_bits(tiled.m[o], whole.m[o])) << names[o];
}

bool moved_and_flowed(const Maps& m, const Fields& f) {
  float water = 0.0f, speed = 0.0f;
  for (float v : m.m[4]) water = std::max(water, v);
  for (float v : m.m[5]) speed = std::max(speed, v);
  return !same_bits(m.m[0], f.f[0]->data) && water > 0.0f && speed > 0.0f;
}

TEST(PipeAcrossTiles, EveryTilingEqualsTheWholeDomainRunBitForBit) {
  const Fields f = fields({65, 49}, 3);
  for (const bool drops : {false, true})
    for (const bool linked : {false, true}) {
      const auto set = node_params(drops);
      PipeStats stats;
      const Maps whole = whole_domain(f, pipe_params(set), linked, &stats);
      ASSERT_TRUE(moved_and_flowed(whole, f)) << "the storm must erode and run";
      ASSERT_GT(stats.steps, 20);
      const auto algorithm = algorithm_of(set, f.domain);
      ASSERT_TRUE(algorithm);
      for (const glm::ivec2 counts : {glm::ivec2(1, 1), glm::ivec2(2, 2), glm::ivec2(3, 2), glm::ivec2(4, 3),
                                      glm::ivec2(1, 4), glm::ivec2(5, 1), glm::ivec2(7, 6)}) {
        SCOPED_TRACE(std::string(drops ? "drops" : "uniform") + (linked ? ", fields linked" : "") + ", tiles " +
                     test::tiles_text(counts));
        int rounds = 0;
        expect_same(across_tiles(*algorithm, f, counts, linked, &rounds), whole);
        EXPECT_EQ(rounds, 1 + stats.steps) << "a round for the static halos, then one per step";
      }
    }
}

// Tiles of 2 and 3 samples: a halo sample then lies in the tile beyond the neighbor.
TEST(PipeAcrossTiles, TilesNarrowerThanTheHaloTakeItFromTheTilesBeyond) {
  const Fields f = fields({41, 33}, 4);
  for (const bool drops : {false, true}) {
    const auto set = node_params(drops);
    const Maps whole = whole_domain(f, pipe_params(set), true, nullptr);
    const auto algorithm = algorithm_of(set, f.domain);
    for (const glm::ivec2 counts : {glm::ivec2(40, 1), glm::ivec2(20, 16), glm::ivec2(13, 32)}) {
      SCOPED_TRACE(std::string(drops ? "drops" : "uniform") + ", tiles " + test::tiles_text(counts));
      int rounds = 0;
      expect_same(across_tiles(*algorithm, f, counts, true, &rounds), whole);
    }
  }
}

// The mutation check: one tile missing one halo exchange (its halo stays a step old) changes the result, so the
// equality above depends on every exchange.
TEST(PipeAcrossTiles, SkippingOneHaloExchangeBreaksTheEquality) {
  const Fields f = fields({65, 49}, 3);
  const auto set = node_params(false);
  const Maps whole = whole_domain(f, pipe_params(set), true, nullptr);
  const auto algorithm = algorithm_of(set, f.domain);
  int rounds = 0;
  expect_same(across_tiles(*algorithm, f, {3, 2}, true, &rounds), whole);
  for (const int round : {2, 9}) {
    SCOPED_TRACE("stale halo in round " + std::to_string(round));
    int disagreements = 0;
    const Maps mutated = across_tiles(
        *algorithm, f, {3, 2}, true, &rounds, [&](std::size_t tile, int r) { return tile == 4 && r == round; },
        &disagreements);
    EXPECT_FALSE(same_bits(mutated.m[0], whole.m[0]));
    EXPECT_GT(disagreements, 0) << "the stale tile's border must differ from its neighbors'";
  }
}

// No rain and no duration: the tiles give back the input, as the whole-domain run does.
TEST(PipeAcrossTiles, AZeroDurationRunsNoStep) {
  const Fields f = fields({33, 33}, 5);
  auto set = node_params(true);
  set["duration"] = 0.0;
  const Maps whole = whole_domain(f, pipe_params(set), true, nullptr);
  int rounds = 0;
  expect_same(across_tiles(*algorithm_of(set, f.domain), f, {2, 3}, true, &rounds), whole);
  EXPECT_EQ(rounds, 1);
}

// Water that overflows makes the time step 0: the tiles fail with the whole-domain run's error, at the same step.
TEST(PipeAcrossTiles, OverflowingWaterIsTheWholeDomainRunsError) {
  Fields f = fields({33, 33}, 6);
  for (auto& v : std::const_pointer_cast<Heightfield>(f.f[2])->data) v = 3e38f;
  auto set = node_params(false);
  set["duration"] = 1e4;
  std::string whole, tiled;
  try {
    whole_domain(f, pipe_params(set), true, nullptr);
  } catch (const NodeError& e) {
    whole = e.what();
  }
  try {
    int rounds = 0;
    across_tiles(*algorithm_of(set, f.domain), f, {3, 2}, true, &rounds);
  } catch (const NodeError& e) {
    tiled = e.what();
  }
  EXPECT_NE(whole.find("PipeErosion: the CFL time step became"), std::string::npos) << whole;
  EXPECT_EQ(tiled, whole);
}

// What travels per step is the tiles' border bands, not the tiles; damaged bytes are refused.
TEST(PipeAcrossTiles, BandsAreSmallAndTheirBytesAreChecked) {
  const Fields f = fields({65, 49}, 3);
  const auto algorithm = algorithm_of(node_params(false), f.domain);
  auto tiles = test::start_tiles(*algorithm, f.domain, {2, 2}, {f.f[0]});
  std::vector<std::string> messages;
  for (auto& tile : tiles) messages.push_back(tile->message(0));
  const std::size_t header = 8 * 4 + 2 * 8 + 4;
  // Tile (0, 0) is 33 x 25 samples with neighbors right and below: 2 rows of 33 and 2 columns of 25 heights.
  EXPECT_EQ(messages[0].size(), header + 4u * (2 * 33 + 2 * 25));
  const auto first = algorithm->solve(0, messages);
  for (std::size_t t = 0; t < tiles.size(); ++t) tiles[t]->answer(0, first[t]);
  messages.clear();
  for (auto& tile : tiles) messages.push_back(tile->message(1));
  // After a step: the seven fields a step reads.
  EXPECT_EQ(messages[0].size(), header + 7u * 4u * (2 * 33 + 2 * 25));
  test::expect_damaged_bytes_refused(*algorithm, tiles, 1, messages);
}

}  // namespace
}  // namespace orogen::erosion
