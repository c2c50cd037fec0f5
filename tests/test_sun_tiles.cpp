// SunIllumination across tiles (nodes/climate/sun_across_tiles.cpp): each sun direction's horizon sweep passes its
// lines' hulls from tile to tile in a wavefront of rounds; put together, the tiles' outputs (lit hours and irradiance
// per month, the instant's lit mask and direct irradiance) must equal the whole-domain node's bit for bit on every
// tiling (tiles of 2 and 3 samples included), at latitudes, dates and hours with a low sun whose shadows cross several
// tiles, with all_months on and off. A run that loses one tile's hulls or its frame must not.
#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "graph/calendar.h"
#include "graph/domain.h"
#include "graph/tile_graph.h"
#include "nodes/climate/sun.h"
#include "nodes/climate/sun_across_tiles.h"
#include "support/tile_graph_run.h"

namespace orogen::climate {
namespace {

using test::same_bits;

// Rough random heights (a few metres) on two ridges 60 and 35 m high, one along x and one diagonal, so shadows of a
// low sun run across many tiles whatever its azimuth; 10 m between samples along x, 8 m along y.
HeightfieldPtr terrain(glm::ivec2 size, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const Domain d = Domain::from_extent({0, 0}, {10.0 * (size.x - 1), 8.0 * (size.y - 1)}, size);
  auto z = std::make_shared<Heightfield>(d);
  for (int j = 0; j < size.y; ++j)
    for (int i = 0; i < size.x; ++i) {
      const float ridge = 60.0f * std::max(0.0f, 1.0f - std::abs(j - size.y / 3.0f) / 4.0f);
      const float diagonal = 35.0f * std::max(0.0f, 1.0f - std::abs(i - j - size.x / 4.0f) / 3.0f);
      z->at(i, j) = 4.0f * u(rng) + ridge + diagonal + 0.2f * static_cast<float>(i);
    }
  return z;
}

struct Case {
  double latitude, hour, time_step;
  int day;  // day of the year
  bool all_months;
};

std::vector<int> months_of(const Case& c) {
  std::vector<int> months;
  if (c.all_months)
    for (int m = 1; m <= 12; ++m) months.push_back(m);
  else
    months.push_back(calendar::month_of_day(c.day));
  return months;
}

SunParams params_of(const Case& c) {
  SunParams p;
  p.latitude = c.latitude, p.time_step = c.time_step, p.irradiance = 1000.0;
  return p;
}

// The four outputs, as flat arrays (the images' channels interleaved per sample).
struct Outputs {
  std::vector<float> hours, irradiance, lit, direct;
};

Outputs whole_domain(const Heightfield& z, const Case& c) {
  const auto months = months_of(c);
  const SunDaily d = sun_daily(z, params_of(c), months);
  const SunInstant in = sun_instant(z, params_of(c), calendar::month_of_day(c.day), c.hour);
  return {d.hours->data, d.irradiance->data, in.lit->data, in.direct->data};
}

// Puts a tile's image into `joined`; a shared sample two tiles give differently counts in `disagreements`, or fails
// the test without it.
void join_image(std::vector<float>& joined, const Image& img, int width, int* disagreements) {
  const auto ch = static_cast<std::size_t>(img.channels);
  for (int j = 0; j < img.domain.height(); ++j)
    for (int i = 0; i < img.domain.width(); ++i)
      for (std::size_t k = 0; k < ch; ++k) {
        const std::size_t q = static_cast<std::size_t>(img.domain.first.y + j) * static_cast<std::size_t>(width) +
                              static_cast<std::size_t>(img.domain.first.x + i);
        const float v = img.data[(static_cast<std::size_t>(j) * img.domain.width() + i) * ch + k];
        float& into = joined[q * ch + k];
        if (!std::isnan(into) && std::memcmp(&into, &v, sizeof v) != 0) {
          if (disagreements)
            ++*disagreements;
          else
            ADD_FAILURE() << "tiles disagree on a sample";
        }
        into = v;
      }
}

// The tiles' rounds as the driver runs them, with `hook` on the answers; the outputs put together, and the rounds.
// `disagreements` counts the shared samples on which two tiles differ (none in a correct run).
Outputs across_tiles(const TileGraphAlgorithm& algorithm, const HeightfieldPtr& z, glm::ivec2 counts, int channels,
                     int* rounds = nullptr, const test::AnswerHook& hook = {}, int* disagreements = nullptr) {
  auto tiles = test::start_tiles(algorithm, z->domain, counts, {z});
  const int ran = test::run_rounds(algorithm, tiles, hook);
  if (rounds) *rounds = ran;
  const std::size_t n = z->data.size();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  Outputs o{std::vector<float>(n * static_cast<std::size_t>(channels), nan),
            std::vector<float>(n * static_cast<std::size_t>(channels), nan), std::vector<float>(n, nan),
            std::vector<float>(n, nan)};
  for (auto& tile : tiles) {
    const auto out = tile->outputs();
    join_image(o.hours, *std::get<ImagePtr>(out[0]), z->width(), disagreements);
    join_image(o.irradiance, *std::get<ImagePtr>(out[1]), z->width(), disagreements);
    test::join_tile_map(o.lit, *std::get<HeightfieldPtr>(out[2]), z->width(), disagreements);
    test::join_tile_map(o.direct, *std::get<HeightfieldPtr>(out[3]), z->width(), disagreements);
  }
  return o;
}

bool same(const Outputs& a, const Outputs& b) {
  return same_bits(a.hours, b.hours) && same_bits(a.irradiance, b.irradiance) && same_bits(a.lit, b.lit) &&
         same_bits(a.direct, b.direct);
}

void expect_same(const Outputs& tiled, const Outputs& whole) {
  EXPECT_TRUE(same_bits(tiled.hours, whole.hours)) << "hours";
  EXPECT_TRUE(same_bits(tiled.irradiance, whole.irradiance)) << "irradiance";
  EXPECT_TRUE(same_bits(tiled.lit, whole.lit)) << "lit";
  EXPECT_TRUE(same_bits(tiled.direct, whole.direct)) << "direct";
}

std::unique_ptr<TileGraphAlgorithm> registered(const Case& c, const Domain& whole) {
  return test::algorithm_of("SunIllumination",
                            {{"latitude", c.latitude},
                             {"hour", c.hour},
                             {"time_step", c.time_step},
                             {"day_of_year", std::int64_t{c.day}},
                             {"all_months", c.all_months}},
                            whole);
}

// Low suns: a winter morning far north, a southern winter morning, an evening on the equator, a polar summer's
// midnight sun; all twelve months or the date's only, hourly and finer steps.
const std::vector<Case> kCases = {
    {62.0, 11.5, 1.0, 350, true}, {-35.0, 7.25, 0.5, 170, false}, {0.0, 17.6, 2.0, 80, false},
    {78.0, 23.5, 1.5, 172, true}, {45.0, 15.0, 1.0, 166, true},   {30.0, 6.4, 0.25, 300, false},
};

// The tilings of the tests on 41 x 33 terrains, and tiles of 2 and of 2 or 3 samples.
std::vector<glm::ivec2> tilings() {
  auto t = test::kTilings;
  t.push_back({20, 16});
  return t;
}

TEST(SunTiles, EqualsTheWholeDomainOnEveryTiling) {
  const auto z = terrain({41, 33}, 5);
  for (const Case& c : kCases) {
    SCOPED_TRACE("latitude " + std::to_string(c.latitude) + ", day " + std::to_string(c.day) + ", hour " +
                 std::to_string(c.hour));
    const Outputs whole = whole_domain(*z, c);
    // Shadows at the instant: some cells lit, some not.
    std::size_t lit = 0;
    for (const float v : whole.lit) lit += v > 0.0f;
    if (c.hour != 23.5) {
      EXPECT_GT(lit, 0u);
      EXPECT_LT(lit, whole.lit.size());
    }
    const auto algorithm = registered(c, z->domain);
    ASSERT_NE(algorithm, nullptr);
    for (const glm::ivec2 counts : tilings()) {
      SCOPED_TRACE(test::tiles_text(counts));
      int rounds = 0;
      expect_same(across_tiles(*algorithm, z, counts, static_cast<int>(months_of(c).size()), &rounds), whole);
      EXPECT_EQ(rounds, counts.x + counts.y + 1);  // the setup, the wavefront, the frames
    }
  }
}

// The sun low enough at the instant that its shadows run across several tiles: at 7x6 tiles (about 6 samples wide),
// a cell is shaded by terrain more than two tiles away toward the sun. The shadow's length: the ridge's height over
// the tangent of the sun's elevation.
TEST(SunTiles, LowSunShadowsCrossSeveralTiles) {
  const Case c = kCases[1];
  const glm::dvec3 s = sun_direction(c.latitude, declination_deg(calendar::month_of_day(c.day)), c.hour);
  ASSERT_GT(s.z, 0.0);
  const double tan_e = s.z / std::hypot(s.x, s.y);
  EXPECT_GT(60.0 / tan_e, 3 * 6 * 10.0) << "a 60 m ridge's shadow is longer than three tiles";
}

// Other sizes: square and long domains, the sweeps along x and along y, tiles of a few samples.
TEST(SunTiles, EqualsTheWholeDomainOnOtherSizes) {
  for (const glm::ivec2 size : {glm::ivec2(17, 17), glm::ivec2(64, 9), glm::ivec2(9, 50)}) {
    const auto z = terrain(size, 11);
    for (const Case& c : {kCases[0], kCases[2], kCases[5]}) {
      const Outputs whole = whole_domain(*z, c);
      const auto algorithm = registered(c, z->domain);
      for (const glm::ivec2 counts : {glm::ivec2(1, 1), glm::ivec2(3, 2), glm::ivec2(size.x / 3, size.y / 3),
                                      glm::ivec2(size.x - 1, size.y - 1)}) {
        SCOPED_TRACE(std::to_string(size.x) + "x" + std::to_string(size.y) + " in " + test::tiles_text(counts));
        expect_same(across_tiles(*algorithm, z, counts, static_cast<int>(months_of(c).size())), whole);
      }
    }
  }
}

// Losing one tile's answer of one round must break the result whenever the answer carried anything: a wavefront
// round's hulls (the tile then has no hull for a line entering it and says so) or the last round's frame (its border
// cells would read no line samples from their neighbors, and differ from the neighbors sharing them). Every tile,
// every round, on 3x2 and 4x3 tiles.
TEST(SunTiles, ALostExchangeBreaksIt) {
  const auto z = terrain({41, 33}, 5);
  const Case c = kCases[0];
  const Outputs whole = whole_domain(*z, c);
  const auto algorithm = registered(c, z->domain);
  for (const glm::ivec2 counts : {glm::ivec2(3, 2), glm::ivec2(4, 3)}) {
    int carried = 0;
    for (int round = 1; round <= counts.x + counts.y; ++round)
      for (std::size_t tile = 0; tile < static_cast<std::size_t>(counts.x * counts.y); ++tile) {
        SCOPED_TRACE(test::tiles_text(counts) + ", round " + std::to_string(round) + ", tile " + std::to_string(tile));
        bool dropped_something = false;
        const test::AnswerHook drop = [&](std::size_t t, int r, std::string& answer) {
          if (t != tile || r != round) return true;
          dropped_something = !answer.empty();
          return false;
        };
        bool broken = false;
        try {
          int disagreements = 0;
          broken =
              !same(across_tiles(*algorithm, z, counts, 12, nullptr, drop, &disagreements), whole) || disagreements > 0;
        } catch (const std::invalid_argument& e) {
          broken = std::string(e.what()).find("sun across tiles") != std::string::npos;
        }
        if (dropped_something) {
          ++carried;
          EXPECT_TRUE(broken);
        }
        if (round == counts.x + counts.y) {
          EXPECT_TRUE(dropped_something) << "every tile reads its neighbors' frames";
        }
      }
    EXPECT_GT(carried, 2 * counts.x * counts.y);
  }
}

// Damaged bytes are refused in every kind of round.
TEST(SunTiles, DamagedBytesAreRefused) {
  const auto z = terrain({41, 33}, 5);
  const auto algorithm = registered(kCases[0], z->domain);
  auto tiles = test::start_tiles(*algorithm, z->domain, {3, 2}, {z});
  for (int round = 0; round <= 5; ++round) {
    SCOPED_TRACE("round " + std::to_string(round));
    std::vector<std::string> messages;
    for (auto& tile : tiles) messages.push_back(tile->message(round));
    if (round == 0 || round == 5) test::expect_damaged_bytes_refused(*algorithm, tiles, round, messages);
    const auto answers = algorithm->solve(round, messages);
    for (std::size_t k = 0; k < tiles.size(); ++k) tiles[k]->answer(round, answers[k]);
  }
}

// Parameters the whole-domain node refuses stay with it.
TEST(SunTiles, RefusedParametersStayOnTheWholeDomain) {
  const auto z = terrain({17, 17}, 3);
  SunParams p;
  p.time_step = 0.0;
  EXPECT_THROW(sun_across_tiles(p, {1}, 1, 12.0, z->domain), NodeError);
}

}  // namespace
}  // namespace orogen::climate
