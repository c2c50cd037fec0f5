// Strahler orders across tiles (nodes/hydrology/tile_strahler.h): each tile orders its channel cells from its own
// flow edges and the other tiles' donor summaries at its perimeter, rounds until no summary changes. Put together, the
// tiles' orders must equal the whole-domain strahler_orders on every tiling (tiles two samples wide included), on
// networks whose channels cross tile borders and corners, with and without filled depressions.
#include <algorithm>

#include <gtest/gtest.h>

#include "nodes/hydrology/channels.h"
#include "nodes/hydrology/tile_accumulation.h"
#include "nodes/hydrology/tile_strahler.h"
#include "nodes/hydrology/tile_phases.h"
#include "support/tile_graph_run.h"

namespace orogen::hydrology {
namespace {

using test::edge;
using test::Terrain;

struct Network {
  D8Flow flow;
  std::vector<std::uint8_t> channel;
  std::vector<std::int32_t> order;  // whole-domain Strahler orders
};

// Channels where at least `threshold` cells drain through a cell, on the (optionally epsilon-filled) terrain.
Network network_of(const Terrain& t, bool fill, double threshold) {
  const FlowGrid g = FlowGrid::of(test::domain_of(t));
  std::vector<float> z = t.z;
  if (fill) fill_depressions(g, z, FlatMode::Epsilon);
  Network n{d8_flow(g, z), {}, {}};
  const auto counts = count_d8(g, n.flow);
  for (const double c : counts) n.channel.push_back(c >= threshold);
  n.order = strahler_orders(g, n.flow, stack_order(g, n.flow), n.channel);
  return n;
}

// The orders across the tiles of `counts`, every message through its bytes; `rounds` gets the rounds run.
std::vector<std::int32_t> tiled_orders(const Terrain& t, const Network& n, glm::ivec2 counts, int& rounds) {
  std::vector<std::unique_ptr<TileStrahler>> tiles;
  std::vector<TileRect> rects;
  for (int tj = 0; tj < counts.y; ++tj)
    for (int ti = 0; ti < counts.x; ++ti) {
      TileRect r;
      r.first = {edge(ti, t.size.x, counts.x), edge(tj, t.size.y, counts.y)};
      r.size = glm::ivec2(edge(ti + 1, t.size.x, counts.x), edge(tj + 1, t.size.y, counts.y)) - r.first + 1;
      std::vector<std::uint8_t> direction, channel;
      for (int j = 0; j < r.size.y; ++j)
        for (int i = 0; i < r.size.x; ++i) {
          const auto c = static_cast<std::size_t>(r.first.y + j) * t.size.x + r.first.x + i;
          direction.push_back(n.flow.direction[c]);
          channel.push_back(n.channel[c]);
        }
      auto receiver = start_tile_accumulation(direction, r, t.size).receiver;
      tiles.push_back(std::make_unique<TileStrahler>(std::move(receiver), std::move(channel), r, t.size));
      rects.push_back(r);
    }
  for (rounds = 1;; ++rounds) {
    std::vector<std::string> messages;
    for (auto& tile : tiles) messages.push_back(tile->message());
    const auto answers = solve_strahler_perimeters(message_views(messages), t.size);
    for (std::size_t k = 0; k < tiles.size(); ++k) tiles[k]->answer(answers[k]);
    if (!strahler_changed(message_views(messages))) break;
    if (rounds > 1000) throw std::logic_error("the rounds do not end");
  }
  std::vector<std::int32_t> joined(t.z.size(), -1);
  for (std::size_t k = 0; k < tiles.size(); ++k) {
    const TileRect& r = rects[k];
    // The tile's orders on every cell, 0 off its channel cells.
    std::vector<std::int32_t> order(static_cast<std::size_t>(r.size.x) * static_cast<std::size_t>(r.size.y), 0);
    const auto& cells = tiles[k]->cells();
    const auto& orders = tiles[k]->orders();
    EXPECT_EQ(cells.size(), orders.size()) << "an order per channel cell";
    for (std::size_t u = 0; u < std::min(cells.size(), orders.size()); ++u)
      order[static_cast<std::size_t>(cells[u])] = orders[u];
    for (int j = 0; j < r.size.y; ++j)
      for (int i = 0; i < r.size.x; ++i) {
        std::int32_t& v = joined[static_cast<std::size_t>(r.first.y + j) * t.size.x + r.first.x + i];
        const std::int32_t mine = order[static_cast<std::size_t>(j * r.size.x + i)];
        EXPECT_TRUE(v < 0 || v == mine) << "tiles disagree on a shared sample";
        v = mine;
      }
  }
  return joined;
}

TEST(StrahlerAcrossTiles, EqualsTheWholeDomainOrdersOnEveryTiling) {
  int highest_order = 0, most_rounds = 0;
  for (const glm::ivec2 size : {glm::ivec2(41, 33), glm::ivec2(129, 97)})
    for (int levels : {0, 2})
      for (const bool fill : {true, false})
        for (const double threshold : {1.0, 6.0, 40.0}) {
          SCOPED_TRACE(test::tiles_text(size) + " levels " + std::to_string(levels) + (fill ? " fill" : " no fill") +
                       " threshold " + std::to_string(threshold));
          const Terrain t = test::terrain(size, 31, levels);
          const Network n = network_of(t, fill, threshold);
          for (const std::int32_t o : n.order) highest_order = std::max(highest_order, o);
          for (const glm::ivec2 counts : test::kTilings) {
            SCOPED_TRACE("tiles " + test::tiles_text(counts));
            int rounds = 0;
            EXPECT_EQ(tiled_orders(t, n, counts, rounds), n.order);
            most_rounds = std::max(most_rounds, rounds);
          }
        }
  EXPECT_GE(highest_order, 4) << "the networks must branch";
  EXPECT_GE(most_rounds, 4) << "orders must travel through several tiles";
}

TEST(StrahlerAcrossTiles, RefusesMalformedInput) {
  const TileRect r{{0, 0}, {3, 3}};
  EXPECT_THROW(TileStrahler({-1, -1}, std::vector<std::uint8_t>(9, 1), r, {3, 3}), std::invalid_argument);
  std::vector<std::int32_t> loop(9, -1);
  loop[4] = 5, loop[5] = 4;
  EXPECT_THROW(TileStrahler(loop, std::vector<std::uint8_t>(9, 1), r, {3, 3}), std::invalid_argument);
  TileStrahler tile(std::vector<std::int32_t>(9, -1), std::vector<std::uint8_t>(9, 1), r, {3, 3});
  const std::string m = tile.message();
  EXPECT_EQ(solve_strahler_perimeters(message_views({m}), {3, 3}).size(), 1u);
  EXPECT_THROW(solve_strahler_perimeters(message_views({m.substr(0, m.size() - 1)}), {3, 3}), std::invalid_argument);
  EXPECT_THROW(solve_strahler_perimeters(message_views({m}), {2, 2}), std::invalid_argument);  // the tile lies outside
  EXPECT_THROW(tile.answer("\x01"), std::invalid_argument);
}

}  // namespace
}  // namespace orogen::hydrology
