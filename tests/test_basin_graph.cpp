// Basin-graph depression routing (nodes/hydrology/basin_graph.h, Cordonnier, Bovy & Braun 2019) against the
// Priority-Flood routing of flow_routing.h and brute-force references, on random terrains with depressions.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <bit>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "nodes/hydrology/basin_graph.h"
#include "nodes/hydrology/flow_routing.h"
#include "support/depression_terrain.h"

namespace orogen::hydrology {
namespace {

// Hills with many closed depressions of every size; the seed also moves the hills.
std::vector<float> bumpy(const FlowGrid& g, std::uint32_t seed, double noise = 3.0) {
  return test::depression_terrain(g, seed, noise, seed);
}

bool neighbours(const FlowGrid& g, std::int32_t a, std::int32_t b) {
  const int di = g.column(b) - g.column(a), dj = g.row(b) - g.row(a);
  return a != b && std::abs(di) <= 1 && std::abs(dj) <= 1;
}

// The structural invariants: receivers are 8-neighbours with a matching direction, donors mirror them, the
// stack is a permutation with every cell after its receiver, each outlet tree starts with its outlet and
// receivers stay inside the tree; receiver == self exactly at the outlets.
void expect_valid_routing(const FlowGrid& g, const BasinRouting& r, const Outlets& outlets) {
  const std::size_t n = g.size();
  const D8Flow& f = r.flow;
  ASSERT_EQ(f.receiver.size(), n);
  ASSERT_EQ(r.stack.size(), n);
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(n); ++c) {
    const bool outlet = outlets.is_outlet(g, g.column(c), g.row(c));
    if (f.receiver[c] == c) {
      EXPECT_TRUE(outlet) << "cell " << c << " is a pit";
      EXPECT_EQ(f.direction[c], kNoDirection);
      continue;
    }
    EXPECT_FALSE(outlet);
    ASSERT_TRUE(neighbours(g, c, f.receiver[c]));
    ASSERT_EQ(c + g.offset(f.direction[c]), f.receiver[c]);
    const std::int32_t rc = f.receiver[c];
    EXPECT_TRUE(f.donors[rc] & (1u << opposite(f.direction[c])));
  }
  int donor_bits = 0, flows = 0;
  for (std::size_t c = 0; c < n; ++c)
    donor_bits += std::popcount(f.donors[c]), flows += f.receiver[c] != static_cast<std::int32_t>(c);
  EXPECT_EQ(donor_bits, flows);
  std::vector<std::int32_t> pos(n, -1);
  for (std::size_t q = 0; q < n; ++q) {
    ASSERT_EQ(pos[static_cast<std::size_t>(r.stack[q])], -1) << "stack repeats a cell";
    pos[static_cast<std::size_t>(r.stack[q])] = static_cast<std::int32_t>(q);
  }
  ASSERT_EQ(r.tree_begin.front(), 0);
  ASSERT_EQ(r.tree_begin.back(), static_cast<std::int32_t>(n));
  for (std::size_t t = 0; t + 1 < r.tree_begin.size(); ++t) {
    const std::int32_t first = r.tree_begin[t], last = r.tree_begin[t + 1];
    ASSERT_LT(first, last);
    EXPECT_EQ(f.receiver[r.stack[static_cast<std::size_t>(first)]], r.stack[static_cast<std::size_t>(first)]);
    for (std::int32_t q = first + 1; q < last; ++q) {
      const std::int32_t c = r.stack[static_cast<std::size_t>(q)];
      const std::int32_t p = pos[static_cast<std::size_t>(f.receiver[c])];
      EXPECT_GE(p, first);
      EXPECT_LT(p, q) << "receiver after its donor in the stack";
    }
  }
}

// Water crosses every depression over its lowest spill: the highest cell on the flow path from c to the
// outlet equals the Priority-Flood (flat) fill level of c.
void expect_lowest_spill_paths(const FlowGrid& g, const BasinRouting& r, const std::vector<float>& z,
                               const std::vector<float>& flat) {
  const std::size_t n = g.size();
  int wrong = 0;
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(n); ++c) {
    float top = z[c];
    std::int32_t x = c;
    for (std::size_t steps = 0; r.flow.receiver[x] != x && steps <= n; ++steps) {
      x = r.flow.receiver[x];
      top = std::max(top, z[x]);
    }
    ASSERT_EQ(r.flow.receiver[x], x) << "cycle from cell " << c;
    wrong += top != flat[c];
  }
  EXPECT_EQ(wrong, 0);
}

TEST(BasinGraphRouting, CarveRoutesEveryCellOverItsLowestSpill) {
  for (std::uint32_t seed = 1; seed <= 4; ++seed) {
    const FlowGrid g(97 + 13 * seed, 64 + 9 * seed, 10.0, 7.5);
    const std::vector<float> z = bumpy(g, seed);
    std::vector<float> flat = z;
    fill_depressions(g, flat, FlatMode::Flat);
    int lakes = 0;
    for (std::size_t c = 0; c < z.size(); ++c) lakes += flat[c] > z[c];
    ASSERT_GT(lakes, 100) << "the terrain must have depressions";
    BasinRouting r;
    route_basin_graph(g, std::span<const float>(z), {}, r);
    EXPECT_GT(r.pits, 10);
    EXPECT_EQ(r.tree_edges, r.pits);
    expect_valid_routing(g, r, {});
    expect_lowest_spill_paths(g, r, z, flat);
  }
}

// Drainage area from the stack against a brute-force count along the receivers; all of it reaches the outlets.
TEST(BasinGraphRouting, AccumulationMatchesBruteForceAndReachesTheOutlets) {
  const FlowGrid g(120, 90, 4.0, 4.0);
  const std::vector<float> z = bumpy(g, 9);
  BasinRouting r;
  route_basin_graph(g, std::span<const float>(z), {}, r);
  std::vector<double> area(g.size());
  accumulate_stack(g, r, area);
  std::vector<double> brute(g.size(), 0.0);
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(g.size()); ++c)
    for (std::int32_t x = c;; x = r.flow.receiver[x]) {
      brute[static_cast<std::size_t>(x)] += g.cell_area();
      if (r.flow.receiver[x] == x) break;
    }
  EXPECT_EQ(area, brute);
  double at_outlets = 0;
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(g.size()); ++c)
    if (r.flow.receiver[c] == c) at_outlets += area[static_cast<std::size_t>(c)];
  EXPECT_DOUBLE_EQ(at_outlets, g.size() * g.cell_area());
}

// The fill variant against Priority-Flood+epsilon then D8: the same lakes, every cell drains, and the same
// drainage area at every outlet (both send each lake over the same pass).
TEST(BasinGraphRouting, FillVariantMatchesPriorityFloodAreasAtTheOutlets) {
  for (std::uint32_t seed = 11; seed <= 14; ++seed) {
    const FlowGrid g(110, 80, 5.0, 5.0);
    const std::vector<float> z = bumpy(g, seed);
    std::vector<float> flat = z, pf = z;
    fill_depressions(g, flat, FlatMode::Flat);
    fill_depressions(g, pf, FlatMode::Epsilon);
    const D8Flow pf_flow = d8_flow(g, pf);
    const std::vector<double> pf_area = accumulate_d8(g, pf_flow);

    std::vector<float> bg = z;
    std::vector<double> raised(g.size(), 0.0);
    BasinRouting r;
    route_basin_graph_fill(g, std::span<float>(bg), {}, r, raised);
    EXPECT_GT(r.pits, 10);
    expect_valid_routing(g, r, {});
    std::vector<double> area(g.size());
    accumulate_stack(g, r, area);
    int lake_mismatch = 0, outlet_mismatch = 0, not_descending = 0;
    for (std::int32_t c = 0; c < static_cast<std::int32_t>(g.size()); ++c) {
      const std::size_t k = static_cast<std::size_t>(c);
      lake_mismatch += (bg[k] > z[k]) != (flat[k] > z[k]);
      EXPECT_GE(bg[k], flat[k]);
      EXPECT_LE(bg[k] - flat[k], 1e-3f * std::max(1.0f, std::abs(flat[k]))) << "raised far above the spill level";
      EXPECT_EQ(raised[k], static_cast<double>(bg[k]) - static_cast<double>(z[k]));
      if (r.flow.receiver[c] != c) not_descending += !(bg[k] > bg[static_cast<std::size_t>(r.flow.receiver[c])]);
      if (pf_flow.receiver[c] == c) outlet_mismatch += area[k] != pf_area[k];
    }
    EXPECT_EQ(lake_mismatch, 0);
    EXPECT_EQ(not_descending, 0);
    EXPECT_EQ(outlet_mismatch, 0) << "seed " << seed;
    // The filled surface has no pit left: routing it again finds none (the incremental case).
    BasinRouting again;
    route_basin_graph(g, std::span<const float>(bg), {}, again);
    EXPECT_EQ(again.pits, 0);
  }
}

// The double variant StreamPower uses: lakes end within a micrometre of the spill level and drain.
TEST(BasinGraphRouting, DoubleFillDrainsEveryLake) {
  const FlowGrid g(100, 100, 10.0, 10.0);
  const std::vector<float> zf = bumpy(g, 5);
  std::vector<float> flat = zf;
  fill_depressions(g, flat, FlatMode::Flat);
  std::vector<double> z(zf.begin(), zf.end());
  BasinRouting r;
  route_basin_graph_fill(g, std::span<double>(z), {}, r);
  expect_valid_routing(g, r, {});
  for (std::size_t c = 0; c < z.size(); ++c) {
    EXPECT_GE(z[c], static_cast<double>(flat[c]));
    EXPECT_LT(z[c] - flat[c], 1e-4);
  }
  BasinRouting again;
  route_basin_graph(g, std::span<const double>(z), {}, again);
  EXPECT_EQ(again.pits, 0);
}

TEST(BasinGraphRouting, OutletMaskAndNoOutletAtAll) {
  const FlowGrid g(70, 60, 3.0, 3.0);
  const std::vector<float> z = bumpy(g, 3);
  // Sea: every cell below 0 m is an outlet as well as the border.
  std::vector<std::uint8_t> sea(g.size());
  for (std::size_t c = 0; c < z.size(); ++c) sea[c] = z[c] < 0.0f;
  Outlets outs;
  outs.mask = sea;
  BasinRouting r;
  route_basin_graph(g, std::span<const float>(z), outs, r);
  expect_valid_routing(g, r, outs);
  // No outlet: the basin of the lowest pit collects everything.
  Outlets none;
  none.border = false;
  route_basin_graph(g, std::span<const float>(z), none, r);
  int roots = 0;
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(g.size()); ++c) roots += r.flow.receiver[c] == c;
  EXPECT_EQ(roots, 1);
  ASSERT_EQ(r.tree_begin.size(), 2u);
  const std::int32_t root = r.stack.front();
  EXPECT_EQ(z[static_cast<std::size_t>(root)], *std::min_element(z.begin(), z.end()));
}

TEST(BasinGraphRouting, IdenticalForAnyThreadCount) {
  const FlowGrid g(260, 230, 5.0, 5.0);
  const std::vector<float> z0 = bumpy(g, 21);
  auto run = [&](int threads) {
    std::vector<double> z(z0.begin(), z0.end());
    BasinRouting r;
    tbb::task_arena(threads).execute([&] { route_basin_graph_fill(g, std::span<double>(z), {}, r); });
    return std::make_tuple(z, r.flow.receiver, r.stack, r.tree_begin);
  };
  EXPECT_TRUE(run(1) == run(4));
}

}  // namespace
}  // namespace orogen::hydrology
