// RiverExtract across tiles through its registered tile-graph algorithm (nodes/hydrology/rivers_across_tiles.cpp): the
// epsilon fill's rounds, the ring, D8 counts through perimeter links, Strahler orders through perimeter summaries,
// then the channel cells of every tile joined into one network. Every tile must get the whole-domain node's curves
// (same curves, vertices, attributes, parents and order, bit for bit) and its window of the river mask, on every
// tiling (tiles two samples wide included), on terrains whose rivers and lakes cross tile borders and corners.
#include <cstring>
#include <set>

#include <gtest/gtest.h>

#include "nodes/hydrology/rivers.h"
#include "support/tile_graph_run.h"

namespace orogen::hydrology {
namespace {

using test::algorithm_of;
using test::domain_of;
using test::edge;
using test::same_bits;
using test::Terrain;
using test::terrain;

template <class T>
bool same_vector(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// Curves equal bit for bit, in the same order; the first difference, or "".
std::string difference(const Curves& a, const Curves& b) {
  if (a.curves.size() != b.curves.size())
    return std::to_string(a.curves.size()) + " curves against " + std::to_string(b.curves.size());
  for (std::size_t k = 0; k < a.curves.size(); ++k) {
    const Curve &x = a.curves[k], &y = b.curves[k];
    if (x.parent != y.parent) return "curve " + std::to_string(k) + ": parent";
    if (!same_vector(x.points, y.points)) return "curve " + std::to_string(k) + ": points";
    if (!same_vector(x.width, y.width)) return "curve " + std::to_string(k) + ": width";
    if (x.attributes.size() != y.attributes.size()) return "curve " + std::to_string(k) + ": attributes";
    for (const auto& [name, values] : x.attributes)
      if (!y.attributes.count(name) || !same_vector(values, y.attributes.at(name)))
        return "curve " + std::to_string(k) + ": " + name;
  }
  return "";
}

struct Tiled {
  std::vector<CurvesPtr> curves;  // per tile
  std::vector<float> mask;        // joined
  int rounds = 0;
};

Tiled run_rivers(const TileGraphAlgorithm& algorithm, const Terrain& t, glm::ivec2 counts) {
  auto tiles = test::start_tiles(algorithm, t, counts, 2);
  Tiled out;
  out.rounds = test::run_rounds(algorithm, tiles);
  out.mask.assign(t.z.size(), std::numeric_limits<float>::quiet_NaN());
  for (auto& tile : tiles) {
    const auto outputs = tile->outputs();
    out.curves.push_back(std::get<CurvesPtr>(outputs.at(0)));
    test::join_tile_map(out.mask, *std::get<HeightfieldPtr>(outputs.at(1)), t.size.x, nullptr);
  }
  return out;
}

TEST(RiversAcrossTiles, EveryTileGetsTheWholeDomainNetworkAndItsWindowOfTheMask) {
  int most_tiles_crossed = 0;
  std::size_t most_curves = 0;
  for (const glm::ivec2 size : {glm::ivec2(41, 33), glm::ivec2(129, 97)})
    for (int levels : {0, 2})
      for (const double threshold : {800.0, 5000.0})
        for (const bool split : {true, false})
          for (const std::int64_t smoothing : {std::int64_t{0}, std::int64_t{2}}) {
            SCOPED_TRACE(test::tiles_text(size) + " levels " + std::to_string(levels) + " threshold " +
                         std::to_string(threshold) + (split ? " split" : " not split") + " smoothing " +
                         std::to_string(smoothing));
            const Terrain t = terrain(size, 41, levels);
            const Domain whole = domain_of(t);
            RiverParams p;
            p.threshold = threshold;
            p.split_at_lakes = split;
            p.smoothing = static_cast<int>(smoothing);
            p.width_coefficient = 12.0;  // wide enough for the mask to reach across tile borders
            const RiverResult r = extract_rivers(test::heights_of(t), nullptr, p);
            most_curves = std::max(most_curves, r.curves->size());
            const auto algorithm = algorithm_of("RiverExtract",
                                                {{"threshold", threshold},
                                                 {"split_at_lakes", split},
                                                 {"smoothing", smoothing},
                                                 {"width_coefficient", 12.0}},
                                                whole);
            ASSERT_TRUE(algorithm);
            for (const glm::ivec2 counts : test::kTilings) {
              if (counts.x >= 40 && size.x > 41) continue;  // tiles two samples wide: on the small terrain only
              SCOPED_TRACE("tiles " + test::tiles_text(counts));
              const Tiled tiled = run_rivers(*algorithm, t, counts);
              for (const CurvesPtr& c : tiled.curves) {
                ASSERT_TRUE(c);
                ASSERT_EQ(difference(*c, *r.curves), "");
              }
              EXPECT_TRUE(same_bits(tiled.mask, r.mask->data)) << "river_mask";
              for (const Curve& c : r.curves->curves) {
                std::set<int> crossed;
                for (const glm::vec3& q : c.points) {
                  const glm::dvec2 s = whole.to_sample({q.x, q.y});
                  crossed.insert(test::tile_of(static_cast<int>(std::lround(s.x)), static_cast<int>(std::lround(s.y)),
                                               size, counts));
                }
                most_tiles_crossed = std::max(most_tiles_crossed, static_cast<int>(crossed.size()));
              }
            }
          }
  EXPECT_GE(most_curves, 20u) << "the networks must branch";
  EXPECT_GE(most_tiles_crossed, 4) << "some river must cross several tiles";
}

TEST(RiversAcrossTiles, ARainfallWeightKeepsTheNodeOnTheWholeDomain) {
  EXPECT_EQ(tile_graph_unlinked_inputs("RiverExtract"), std::vector<std::string>{"rainfall_weight"});
  const Terrain t = terrain({9, 9}, 3, 0);
  const auto algorithm = algorithm_of("RiverExtract", {}, domain_of(t));
  ASSERT_TRUE(algorithm);
  auto h = std::make_shared<Heightfield>(test::heights_of(t));
  EXPECT_THROW(algorithm->start({HeightfieldPtr(h), HeightfieldPtr(h)}), std::invalid_argument);
  EXPECT_THROW(algorithm->start({}), std::invalid_argument);
  EXPECT_THROW(algorithm->solve(0, {std::string("\x09")}), std::invalid_argument);  // no such phase
}

}  // namespace
}  // namespace orogen::hydrology
