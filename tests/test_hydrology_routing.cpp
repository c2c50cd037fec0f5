// The routing core (nodes/hydrology/flow_routing.h) against brute-force references and analytic cases.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include "nodes/hydrology/flow_routing.h"
#include "nodes/hydrology/flow_shares.h"
#include "support/depression_terrain.h"

namespace orogen::hydrology {
namespace {

using test::hash01;

// Hilly terrain with many closed depressions.
std::vector<float> bumpy(const FlowGrid& g, std::uint32_t seed, double noise = 3.0) {
  return test::depression_terrain(g, seed, noise);
}

// Reference fill: W = max(z, min over neighbours of W) iterated to the fixed point (Planchon & Darboux 2001
// without epsilon), border cells fixed.
std::vector<float> brute_fill(const FlowGrid& g, const std::vector<float>& z) {
  std::vector<float> w(z.size());
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) w[g.index(i, j)] = g.on_border(i, j) ? z[g.index(i, j)] : INFINITY;
  for (bool changed = true; changed;) {
    changed = false;
    for (int j = 1; j < g.ny - 1; ++j)
      for (int i = 1; i < g.nx - 1; ++i) {
        float m = INFINITY;
        for (int k = 0; k < 8; ++k) m = std::min(m, w[g.index(i + kDi[k], j + kDj[k])]);
        const float v = std::max(z[g.index(i, j)], m);
        if (v < w[g.index(i, j)]) {
          w[g.index(i, j)] = v;
          changed = true;
        }
      }
  }
  return w;
}

// Reference epsilon fill: the definition of FlatMode::Epsilon iterated to its fixed point by Bellman-Ford sweeps
// (e = z at the outlets, e = max(z, min over neighbours of nextafter(e, +inf)) elsewhere, from +inf down).
std::vector<float> brute_epsilon(const FlowGrid& g, const std::vector<float>& z, const Outlets& outlets = {}) {
  std::vector<float> e(z.size());
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) e[g.index(i, j)] = outlets.is_outlet(g, i, j) ? z[g.index(i, j)] : INFINITY;
  for (bool changed = true; changed;) {
    changed = false;
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        if (outlets.is_outlet(g, i, j)) continue;
        float m = INFINITY;
        for (int k = 0; k < 8; ++k)
          if (g.inside(i + kDi[k], j + kDj[k])) m = std::min(m, e[g.index(i + kDi[k], j + kDj[k])]);
        const float v = std::max(z[g.index(i, j)], std::nextafter(m, INFINITY));
        if (v < e[g.index(i, j)]) {
          e[g.index(i, j)] = v;
          changed = true;
        }
      }
  }
  return e;
}

int count_pits(const FlowGrid& g, const std::vector<float>& z) {
  int pits = 0;
  for (int j = 1; j < g.ny - 1; ++j)
    for (int i = 1; i < g.nx - 1; ++i) {
      bool lower = false;
      for (int k = 0; k < 8; ++k) lower |= z[g.index(i + kDi[k], j + kDj[k])] < z[g.index(i, j)];
      pits += !lower;
    }
  return pits;
}

TEST(HydrologyFill, FlatMatchesBruteForceOnRandomGrids) {
  for (std::uint32_t seed = 1; seed <= 12; ++seed) {
    const FlowGrid g(17 + static_cast<int>(seed % 5) * 7, 23 + static_cast<int>(seed % 3) * 5, 2.0, 3.0);
    std::vector<float> z(g.size());
    for (std::size_t c = 0; c < z.size(); ++c)
      z[c] = std::floor(hash01(seed * 1000003u + static_cast<std::uint32_t>(c)) * 20.0f);
    std::vector<float> out = z;
    fill_depressions(g, out, FlatMode::Flat);
    EXPECT_EQ(out, brute_fill(g, z)) << "seed " << seed;
  }
  // Larger hilly grids (long queues, many depressions), also with an interior outlet.
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    const FlowGrid g(150, 120, 4.0, 4.0);
    const std::vector<float> z = bumpy(g, seed, 6.0);
    std::vector<float> out = z;
    fill_depressions(g, out, FlatMode::Flat);
    EXPECT_EQ(out, brute_fill(g, z)) << "seed " << seed;
  }
}

// The epsilon surface is one function of the heights, whatever order a flood visits ties in: bit for bit the
// fixed point of its definition, on grids made of ties (a few integer levels: wide flats, plateaus, lakes whose
// floors are flat) and continuous ones, negative heights, and an interior outlet mask. Filling the Flat-filled
// heights gives the same surface (what the fill across tiles builds on).
TEST(HydrologyFill, EpsilonIsTheLeastFixedPointOfItsDefinitionBitForBit) {
  int raised = 0;
  for (std::uint32_t seed = 1; seed <= 40; ++seed) {
    const FlowGrid g(9 + static_cast<int>(seed % 7) * 5, 7 + static_cast<int>(seed % 5) * 6, 2.0, 3.0);
    const int levels = seed % 4 == 3 ? 0 : 2 + static_cast<int>(seed % 4);
    const float base = seed % 2 ? 100.0f : -37.5f;
    std::vector<float> z(g.size());
    for (std::size_t c = 0; c < z.size(); ++c) {
      const float u = hash01(seed * 7919u + static_cast<std::uint32_t>(c));
      z[c] = base + (levels ? std::floor(u * static_cast<float>(levels)) : u * 3.0f);
    }
    std::vector<std::uint8_t> mask;
    Outlets outlets;
    if (seed % 5 == 0) {
      mask.assign(g.size(), 0);
      mask[static_cast<std::size_t>(g.index(g.nx / 2, g.ny / 2))] = 1;
      outlets.mask = mask;
    }
    SCOPED_TRACE("seed " + std::to_string(seed));
    const std::vector<float> expected = brute_epsilon(g, z, outlets);
    std::vector<float> out = z;
    fill_depressions(g, out, FlatMode::Epsilon, outlets);
    ASSERT_EQ(0, std::memcmp(out.data(), expected.data(), out.size() * sizeof(float)));
    // The incremental form from the outlets, with the seeds in a scrambled order.
    std::vector<float> relaxed(g.size(), INFINITY);
    std::vector<std::int32_t> seeds;
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i)
        if (outlets.is_outlet(g, i, j)) seeds.push_back(g.index(i, j)), relaxed[g.index(i, j)] = z[g.index(i, j)];
    std::reverse(seeds.begin(), seeds.end());
    relax_epsilon(g.nx, g.ny, z, relaxed, seeds);
    ASSERT_EQ(0, std::memcmp(relaxed.data(), expected.data(), out.size() * sizeof(float)));
    std::vector<float> flat = z;
    fill_depressions(g, flat, FlatMode::Flat, outlets);
    std::vector<float> from_flat = flat;
    fill_depressions(g, from_flat, FlatMode::Epsilon, outlets);
    ASSERT_EQ(0, std::memcmp(from_flat.data(), expected.data(), out.size() * sizeof(float)));
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) {
        const std::int32_t c = g.index(i, j);
        ASSERT_GE(out[c], flat[c]);
        raised += out[c] > z[c];
        if (outlets.is_outlet(g, i, j)) {
          ASSERT_EQ(out[c], z[c]);
          continue;
        }
        bool lower = false;
        for (int k = 0; k < 8; ++k)
          lower |= g.inside(i + kDi[k], j + kDj[k]) && out[g.index(i + kDi[k], j + kDj[k])] < out[c];
        ASSERT_TRUE(lower) << "cell " << i << "," << j << " has no strictly lower neighbour";
      }
  }
  EXPECT_GT(raised, 1000);
}

TEST(HydrologyFill, EpsilonLeavesNoPitAndStaysCloseToFlatFill) {
  const FlowGrid g(96, 80, 5.0, 5.0);
  const std::vector<float> z = bumpy(g, 3);
  const std::vector<float> flat = brute_fill(g, z);
  std::vector<float> out = z;
  fill_depressions(g, out, FlatMode::Epsilon);
  EXPECT_GT(count_pits(g, z), 5);
  EXPECT_EQ(count_pits(g, out), 0);
  int drained = 0;
  for (std::size_t c = 0; c < z.size(); ++c) {
    ASSERT_GE(out[c], z[c]);
    ASSERT_GE(out[c], flat[c]);
    ASSERT_LE(out[c] - flat[c], 1e-3f * std::max(1.0f, std::abs(flat[c])));
    if (flat[c] == z[c]) {
      ++drained;
      ASSERT_EQ(out[c], z[c]) << "a cell that drains is unchanged";
    }
  }
  EXPECT_GT(drained, static_cast<int>(z.size() / 2));
  // Every cell has a strictly descending D8 path to the border.
  const D8Flow f = d8_flow(g, out);
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(g.size()); ++c) {
    std::int32_t x = c;
    while (f.receiver[x] != x) x = f.receiver[x];
    ASSERT_TRUE(g.on_border(g.column(x), g.row(x)));
  }
}

TEST(HydrologyFill, EpsilonFillReportsTheFlatWaterLevel) {
  const FlowGrid g(120, 100, 5.0, 5.0);
  const std::vector<float> z = bumpy(g, 8);
  std::vector<float> eps = z, level(g.size());
  fill_depressions(g, eps, FlatMode::Epsilon, {}, nullptr, level);
  const std::vector<float> flat = brute_fill(g, z);
  int lakes = 0;
  for (std::size_t c = 0; c < z.size(); ++c) {
    ASSERT_EQ(level[c], flat[c]) << "exactly the flat fill";
    ASSERT_LE(level[c], eps[c]);
    lakes += flat[c] > z[c];
  }
  EXPECT_GT(lakes, 100);
  std::vector<float> f2 = z, level2(g.size());
  fill_depressions(g, f2, FlatMode::Flat, {}, nullptr, level2);
  EXPECT_EQ(level2, f2);
}

TEST(HydrologyFill, BowlFillsExactlyToItsRim) {
  // A paraboloid bowl inside a rim at 10 m with one notch at 8 m that opens to low ground.
  const FlowGrid g(41, 41, 1.0, 1.0);
  std::vector<float> z(g.size());
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const double r = std::hypot(i - 20.0, j - 20.0);
      z[g.index(i, j)] = r < 12 ? static_cast<float>(r * r / 30.0) : (r < 14 ? 10.0f : 0.0f);
    }
  for (int i = 32; i < 35; ++i) z[g.index(i, 20)] = 8.0f;  // the notch through the rim
  std::vector<float> out = z;
  fill_depressions(g, out, FlatMode::Flat);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const std::size_t c = g.index(i, j);
      const double r = std::hypot(i - 20.0, j - 20.0);
      if (r < 12) {
        ASSERT_EQ(out[c], std::max(z[c], 8.0f)) << i << "," << j;
      } else {
        ASSERT_EQ(out[c], z[c]) << i << "," << j;
      }
    }
}

TEST(HydrologyFill, ExtraOutletsDrainTheirDepressions) {
  const FlowGrid g(30, 30, 1.0, 1.0);
  std::vector<float> z(g.size());
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) z[g.index(i, j)] = static_cast<float>(std::hypot(i - 15.0, j - 15.0));
  std::vector<std::uint8_t> mask(g.size(), 0);
  mask[g.index(15, 15)] = 1;
  std::vector<float> out = z;
  fill_depressions(g, out, FlatMode::Flat, Outlets{true, mask});
  EXPECT_EQ(out, z);
  fill_depressions(g, out, FlatMode::Flat);
  EXPECT_GT(out[g.index(15, 15)], 10.0f);
}

TEST(HydrologyBreach, CarvesWithoutRaisingAndLeavesNoPit) {
  const FlowGrid g(80, 72, 4.0, 4.0);
  const std::vector<float> z = bumpy(g, 5);
  std::vector<float> out = z;
  breach_depressions(g, out, FlatMode::Epsilon);
  for (std::size_t c = 0; c < z.size(); ++c) ASSERT_LE(out[c], z[c]);
  EXPECT_GT(count_pits(g, z), 5);
  EXPECT_EQ(count_pits(g, out), 0);
  int changed = 0;
  for (std::size_t c = 0; c < z.size(); ++c) changed += out[c] != z[c];
  EXPECT_GT(changed, 0);
  EXPECT_LT(changed, static_cast<int>(z.size() / 4));
}

TEST(HydrologyD8, ReceiversAreSteepestDescentInWorldUnits) {
  const FlowGrid g(40, 33, 2.0, 5.0);
  const std::vector<float> z = bumpy(g, 9, 10.0);
  const D8Flow f = d8_flow(g, z);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const std::int32_t c = g.index(i, j);
      if (g.on_border(i, j)) {
        ASSERT_EQ(f.receiver[c], c);
        continue;
      }
      double best = 0.0;
      std::int32_t want = c;
      for (int k = 0; k < 8; ++k) {
        const double dist = std::hypot(kDi[k] * g.dx, kDj[k] * g.dy);
        const std::int32_t n = g.index(i + kDi[k], j + kDj[k]);
        const double s = (static_cast<double>(z[c]) - z[n]) / dist;
        if (s > best) {
          best = s;
          want = n;
        }
      }
      ASSERT_EQ(f.receiver[c], want) << i << "," << j;
      if (want != c) {
        ASSERT_TRUE(f.donors[want] & (1u << opposite(f.direction[c])));
      }
    }
}

// The vectorised D8 pass and the band-parallel accumulation against plain per-cell references, bit for bit:
// quantised heights (ties and flats), an odd width (scalar tail), an outlet mask, 1, 2 and 4 threads on a
// grid large enough for the parallel path (>= 65536 cells, several bands).
TEST(HydrologyD8, VectorisedPassesMatchScalarReferenceBitForBit) {
  const FlowGrid g(301, 263, 4.0, 3.0);
  std::vector<float> z = bumpy(g, 31, 6.0);
  for (float& v : z) v = std::round(v * 0.5f) * 2.0f;
  std::vector<std::uint8_t> mask(g.size(), 0);
  for (std::size_t c = 0; c < g.size(); c += 997) mask[c] = 1;
  Outlets o;
  o.mask = mask;
  // Reference receivers: the same slope formula, strict > in increasing k.
  std::vector<std::int32_t> want(g.size());
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      const std::int32_t c = g.index(i, j);
      want[c] = c;
      if (o.is_outlet(g, i, j)) continue;
      double best = 0.0;
      for (int k = 0; k < 8; ++k) {
        if (!g.inside(i + kDi[k], j + kDj[k])) continue;
        const double s = (static_cast<double>(z[c]) - z[g.index(i + kDi[k], j + kDj[k])]) * (1.0 / g.distance(k));
        if (s > best) {
          best = s;
          want[c] = g.index(i + kDi[k], j + kDj[k]);
        }
      }
    }
  std::vector<float> w(g.size());
  for (std::size_t c = 0; c < g.size(); ++c) w[c] = 1.0f + hash01(static_cast<std::uint32_t>(c) * 13u + 5u);
  std::vector<double> ref;
  for (int threads : {1, 2, 4}) {
    D8Flow f;
    std::vector<double> acc;
    tbb::task_arena(threads).execute([&] {
      f = d8_flow(g, z, o);
      acc = accumulate_d8(g, f, w);
    });
    ASSERT_EQ(f.receiver, want) << threads << " threads";
    if (ref.empty()) {
      // Reference accumulation: pull in reverse stack order (every donor before its receiver).
      const auto order = stack_order(g, f);
      ref.assign(g.size(), 0.0);
      for (auto it = order.rbegin(); it != order.rend(); ++it) {
        const std::int32_t c = *it;
        double s = w[c];
        for (int k = 0; k < 8; ++k)
          if (f.donors[c] & (1u << k)) s += ref[c + g.offset(k)];
        ref[c] = s;
      }
    }
    ASSERT_EQ(acc, ref) << threads << " threads";
  }
}

TEST(HydrologyD8, StackOrderAndBasins) {
  const FlowGrid g(64, 48, 3.0, 3.0);
  std::vector<float> z = bumpy(g, 11);
  const D8Flow f = d8_flow(g, z);
  const auto order = stack_order(g, f);
  ASSERT_EQ(order.size(), g.size());
  std::vector<int> pos(g.size(), -1);
  for (std::size_t p = 0; p < order.size(); ++p) {
    ASSERT_EQ(pos[order[p]], -1) << "cell listed twice";
    pos[order[p]] = static_cast<int>(p);
  }
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(g.size()); ++c)
    if (f.receiver[c] != c) {
      ASSERT_LT(pos[f.receiver[c]], pos[c]);
    }
  int count = 0;
  const auto label = basin_labels(f, order, &count);
  int outlets = 0;
  for (std::int32_t c = 0; c < static_cast<std::int32_t>(g.size()); ++c) {
    outlets += f.receiver[c] == c;
    ASSERT_EQ(label[c], label[f.receiver[c]]);
  }
  EXPECT_EQ(count, outlets);
}

TEST(HydrologyAccumulation, InclinedPlaneGrowsLinearlyDownslope) {
  const FlowGrid g(50, 40, 10.0, 10.0);
  std::vector<float> z(g.size());
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) z[g.index(i, j)] = static_cast<float>((g.nx - 1 - i) * g.dx * 0.1);
  const auto acc = accumulate_d8(g, d8_flow(g, z));
  for (int j = 1; j < g.ny - 1; ++j)
    for (int i = 1; i < g.nx; ++i) ASSERT_DOUBLE_EQ(acc[g.index(i, j)], i * g.cell_area()) << i << "," << j;
  for (FlowMethod m : {FlowMethod::DInfinity, FlowMethod::MFD}) {
    const auto a = accumulate(g, z, RoutingOptions{m, 1.1, {}});
    for (int i = 1; i < g.nx; ++i) ASSERT_NEAR(a[g.index(i, g.ny / 2)], i * g.cell_area(), 1e-4 * i * g.cell_area());
  }
}

TEST(HydrologyAccumulation, OutletsReceiveTheTotalWeight) {
  const FlowGrid g(70, 60, 4.0, 6.0);
  std::vector<float> z = bumpy(g, 13);
  fill_depressions(g, z, FlatMode::Epsilon);
  std::vector<float> rain(g.size());
  for (std::size_t c = 0; c < rain.size(); ++c) rain[c] = 0.5f + hash01(static_cast<std::uint32_t>(c));
  const double total = std::accumulate(rain.begin(), rain.end(), 0.0);
  for (FlowMethod m : {FlowMethod::D8, FlowMethod::DInfinity, FlowMethod::MFD}) {
    const auto acc = accumulate(g, z, RoutingOptions{m, 1.1, {}}, rain);
    double at_outlets = 0.0;
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i)
        if (g.on_border(i, j)) at_outlets += acc[g.index(i, j)];
    EXPECT_NEAR(at_outlets, total, 1e-9 * total) << static_cast<int>(m);
    for (std::size_t c = 0; c < acc.size(); ++c) ASSERT_GE(acc[c], rain[c] * (1 - 1e-12));
  }
}

TEST(HydrologyAccumulation, ConeMatchesAnalyticSpecificCatchmentArea) {
  // Flow diverging from the top of a cone: specific catchment area a = A / b = r / 2 (Tarboton 1997). The
  // ring mean of acc / dx grows like r / 2; the constant differs from 1 by the cells a flow line visits per
  // metre (D-infinity splits by angle: 0.92 at 20 degrees), so the ratio is bounded and independent of r.
  const FlowGrid g(161, 161, 1.0, 1.0);
  std::vector<float> z(g.size());
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) z[g.index(i, j)] = static_cast<float>(100.0 - std::hypot(i - 80.0, j - 80.0));
  for (FlowMethod m : {FlowMethod::DInfinity, FlowMethod::MFD}) {
    const auto acc = accumulate(g, z, RoutingOptions{m, 1.1, {}});
    auto ratio = [&](double r0, double r1) {
      double s = 0.0;
      int n = 0;
      for (int j = 0; j < g.ny; ++j)
        for (int i = 0; i < g.nx; ++i) {
          const double r = std::hypot(i - 80.0, j - 80.0);
          if (r < r0 || r >= r1) continue;
          s += acc[g.index(i, j)] / g.dx / (r / 2);
          ++n;
        }
      return s / n;
    };
    const double inner = ratio(25, 30), outer = ratio(60, 65);
    EXPECT_NEAR(inner, 1.0, 0.12) << static_cast<int>(m);
    EXPECT_NEAR(outer, 1.0, 0.12) << static_cast<int>(m);
    EXPECT_NEAR(outer / inner, 1.0, 0.03) << static_cast<int>(m);
  }
}

TEST(HydrologyAccumulation, ProportionsAreNonNegativeAndSumToOne) {
  const FlowGrid g(30, 30, 2.0, 3.0);
  const std::vector<float> z = bumpy(g, 17, 8.0);
  for (FlowMethod m : {FlowMethod::D8, FlowMethod::DInfinity, FlowMethod::MFD})
    for (double p : {1.0, 1.1, 8.0})
      for (int j = 1; j < g.ny - 1; ++j)
        for (int i = 1; i < g.nx - 1; ++i) {
          int nb[8];
          double fr[8];
          const int n = flow_proportions(g, z, i, j, RoutingOptions{m, p, {}}, nb, fr);
          if (n == 0) continue;
          double s = 0;
          for (int q = 0; q < n; ++q) {
            ASSERT_GE(fr[q], 0.0);
            ASSERT_LT(z[g.index(i + kDi[nb[q]], j + kDj[nb[q]])], z[g.index(i, j)]) << "flow goes downhill";
            s += fr[q];
          }
          ASSERT_NEAR(s, 1.0, 1e-12);
          if (m != FlowMethod::MFD) {
            ASSERT_LE(n, m == FlowMethod::D8 ? 1 : 2);
          }
        }
}

TEST(HydrologyAccumulation, DeterministicForAnyThreadCount) {
  const FlowGrid g(300, 260, 5.0, 5.0);
  std::vector<float> z = bumpy(g, 21);
  fill_depressions(g, z, FlatMode::Epsilon);
  std::vector<double> one, four;
  tbb::task_arena(1).execute([&] { one = accumulate_d8(g, d8_flow(g, z)); });
  tbb::task_arena(4).execute([&] { four = accumulate_d8(g, d8_flow(g, z)); });
  EXPECT_EQ(one, four);
  for (FlowMethod m : {FlowMethod::DInfinity, FlowMethod::MFD}) {
    tbb::task_arena(1).execute([&] { one = accumulate(g, z, RoutingOptions{m, 1.1, {}}); });
    tbb::task_arena(4).execute([&] { four = accumulate(g, z, RoutingOptions{m, 1.1, {}}); });
    EXPECT_EQ(one, four);
  }
}

// The banded parallel accumulation (bands merged up a fixed tree) against a plain serial reference: every cell
// in decreasing height pushes its total to its receivers (heights strictly decrease downstream after the
// epsilon fill). Tall enough for several bands (one of them short); equal for 1, 2, 3 and 4 threads.
TEST(HydrologyAccumulation, BandedAccumulationMatchesSerialReference) {
  const FlowGrid g(90, 333, 5.0, 4.0);
  std::vector<float> z = bumpy(g, 17);
  fill_depressions(g, z, FlatMode::Epsilon);
  std::vector<float> rain(g.size());
  for (std::size_t c = 0; c < rain.size(); ++c) rain[c] = 0.25f + hash01(static_cast<std::uint32_t>(c) * 3u + 1u);
  std::vector<std::int32_t> by_height(g.size());
  std::iota(by_height.begin(), by_height.end(), 0);
  std::stable_sort(by_height.begin(), by_height.end(), [&](std::int32_t a, std::int32_t b) { return z[a] > z[b]; });
  for (FlowMethod m : {FlowMethod::DInfinity, FlowMethod::MFD}) {
    const RoutingOptions opt{m, 1.7, {}};
    std::vector<double> ref(rain.begin(), rain.end());
    for (std::int32_t c : by_height) {
      int nb[8];
      double fr[8];
      const int n = flow_proportions(g, z, g.column(c), g.row(c), opt, nb, fr);
      for (int k = 0; k < n; ++k) ref[c + g.offset(nb[k])] += ref[c] * fr[k];
    }
    std::vector<double> one;
    tbb::task_arena(1).execute([&] { one = accumulate(g, z, opt, rain); });
    // 1e-6: D-infinity keeps its split in single precision.
    for (std::size_t c = 0; c < ref.size(); ++c) ASSERT_NEAR(one[c], ref[c], 1e-6 * ref[c]) << c;
    for (int threads : {2, 3, 4}) {
      std::vector<double> more;
      tbb::task_arena(threads).execute([&] { more = accumulate(g, z, opt, rain); });
      ASSERT_EQ(more, one) << threads << " threads";
    }
  }
}

// The shares that accumulate keeps (MFD: the weights in one array found by blocks of cells, the normaliser added
// again) give every cell's every proportion bit for bit as flow_proportions computes it, border cells and a last
// partial block included, with and without an outlet mask; cells with no receiver have none.
TEST(HydrologyAccumulation, SharesGiveEveryProportionBitForBit) {
  const FlowGrid g(37, 23, 3.0, 5.0);  // 851 cells: not a whole number of 16-cell blocks
  std::vector<float> z = bumpy(g, 29, 4.0);
  std::vector<std::uint8_t> mask(g.size(), 0);
  for (std::size_t c = 0; c < mask.size(); c += 41) mask[c] = 1;
  std::vector<float> rough = z;
  fill_depressions(g, z, FlatMode::Epsilon);
  // Whole metres: ties, several receivers at the steepest slope or at equal slopes.
  std::vector<float> terraced = rough;
  for (float& v : terraced) v = std::round(v);
  int checked = 0, many = 0;
  for (const auto& heights : {z, rough, terraced})
    for (FlowMethod m : {FlowMethod::MFD, FlowMethod::DInfinity, FlowMethod::D8})
      for (const bool masked : {false, true}) {
        RoutingOptions opt{m, 1.3, {}};
        if (masked) opt.outlets.mask = mask;
        const FlowShares shares(g, heights, opt);
        const D8Flow d8 = d8_flow(g, heights, opt.outlets);
        for (int j = 0; j < g.ny; ++j)
          for (int i = 0; i < g.nx; ++i) {
            const std::int32_t c = g.index(i, j);
            int nb[8];
            double fr[8];
            int n = 0;
            if (m == FlowMethod::D8) {
              if (d8.direction[static_cast<std::size_t>(c)] != kNoDirection)
                nb[n] = d8.direction[static_cast<std::size_t>(c)], fr[n++] = 1.0;
            } else {
              n = flow_proportions(g, heights, i, j, opt, nb, fr);
            }
            std::uint8_t bits = 0;
            for (int k = 0; k < n; ++k) bits |= static_cast<std::uint8_t>(1u << nb[k]);
            ASSERT_EQ(shares.receivers(c), bits) << i << "," << j;
            // D-infinity keeps its split in single precision (as accumulate always did): the cardinal receiver
            // (nb[0]) gets it, the diagonal one the rest.
            if (m == FlowMethod::DInfinity && n == 2) {
              fr[0] = static_cast<double>(static_cast<float>(fr[0]));
              fr[1] = 1.0 - fr[0];
            }
            for (int k = 0; k < n; ++k) {
              ASSERT_EQ(shares.fraction(c, nb[k]), fr[k])
                  << i << "," << j << " receiver " << nb[k] << " method " << static_cast<int>(m);
              ++checked;
            }
            many += n >= 4;
          }
      }
  EXPECT_GT(checked, 5000);
  EXPECT_GT(many, 100) << "cells with several receivers must be checked";
}

}  // namespace
}  // namespace orogen::hydrology
