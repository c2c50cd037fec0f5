#include "nodes/hydrology/flow_routing.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <limits>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "graph/exec_context.h"
#include "nodes/field/row_loop.h"

namespace orogen::hydrology {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

void check(const ExecContext* ctx) {
  if (ctx) ctx->check_cancelled();
}

// Min-heap entry of the priority floods; ties broken by index so the order is fully specified.
struct Entry {
  float z;
  std::int32_t c;
};
struct EntryGreater {
  bool operator()(const Entry& a, const Entry& b) const { return a.z > b.z || (a.z == b.z && a.c > b.c); }
};

class MinHeap {
 public:
  void push(float z, std::int32_t c) {
    v_.push_back({z, c});
    std::push_heap(v_.begin(), v_.end(), EntryGreater{});
  }
  Entry pop() {
    std::pop_heap(v_.begin(), v_.end(), EntryGreater{});
    Entry e = v_.back();
    v_.pop_back();
    return e;
  }
  bool empty() const { return v_.empty(); }

 private:
  std::vector<Entry> v_;
};

// The grid with a one-cell frame: neighbours of every interior cell exist, the frame is closed and +inf.
struct Padded {
  int W = 0, H = 0;
  std::int32_t off[8];
  std::vector<float> z;
  std::vector<std::uint8_t> closed;

  Padded(const FlowGrid& g, std::span<const float> src) : W(g.nx + 2), H(g.ny + 2) {
    for (int k = 0; k < 8; ++k) off[k] = kDj[k] * W + kDi[k];
    const std::size_t n = static_cast<std::size_t>(W) * static_cast<std::size_t>(H);
    z.assign(n, kInf);
    closed.assign(n, 1);
    for (int j = 0; j < g.ny; ++j) {
      std::copy_n(src.data() + static_cast<std::size_t>(j) * g.nx, g.nx, z.data() + p(0, j));
      std::fill_n(closed.data() + p(0, j), g.nx, std::uint8_t{0});
    }
  }
  std::int32_t p(int i, int j) const { return (j + 1) * W + (i + 1); }
  void copy_back(const FlowGrid& g, std::span<float> dst) const {
    for (int j = 0; j < g.ny; ++j) std::copy_n(z.data() + p(0, j), g.nx, dst.data() + static_cast<std::size_t>(j) * g.nx);
  }
};

template <class Fn>
void for_each_outlet(const FlowGrid& g, const Outlets& outlets, Fn&& fn) {
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i)
      if (outlets.is_outlet(g, i, j)) fn(i, j);
}

template <bool kEpsilon>
void fill_impl(const FlowGrid& g, std::span<float> z, const Outlets& outlets, const ExecContext* ctx) {
  Padded P(g, z);
  auto step = [](float v) { return kEpsilon ? std::nextafter(v, kInf) : v; };
  MinHeap heap;
  for_each_outlet(g, outlets, [&](int i, int j) {
    const std::int32_t c = P.p(i, j);
    P.closed[c] = 1;
    heap.push(P.z[c], c);
  });
  std::vector<std::int32_t> pit, trace;
  pit.reserve(1024);
  trace.reserve(1024);
  float* zp = P.z.data();
  std::uint8_t* closed = P.closed.data();
  const std::int32_t* off = P.off;
  std::size_t work = 0;
  while (!heap.empty()) {
    const Entry e = heap.pop();
    const float raised = step(zp[e.c]);
    for (int k = 0; k < 8; ++k) {
      const std::int32_t n = e.c + off[k];
      if (closed[n]) continue;
      closed[n] = 1;
      if (zp[n] <= raised) {
        zp[n] = raised;
        pit.push_back(n);
      } else {
        trace.push_back(n);
      }
    }
    // Depression cells: breadth first at the spill level (FIFO keeps the epsilon gradient short).
    for (std::size_t head = 0; head < pit.size(); ++head) {
      const std::int32_t c = pit[head];
      const float r = step(zp[c]);
      for (int k = 0; k < 8; ++k) {
        const std::int32_t n = c + off[k];
        if (closed[n]) continue;
        closed[n] = 1;
        if (zp[n] <= r) {
          zp[n] = r;
          pit.push_back(n);
        } else {
          trace.push_back(n);
        }
      }
    }
    work += pit.size();
    pit.clear();
    // Slope cells: their height is final; climb while no unvisited neighbour could be lower (a potential
    // spill into another depression), otherwise hand the cell to the priority queue.
    while (!trace.empty()) {
      const std::int32_t c = trace.back();
      trace.pop_back();
      ++work;
      const float r = step(zp[c]);
      bool low = false;
      for (int k = 0; k < 8; ++k) {
        const std::int32_t n = c + off[k];
        if (!closed[n] && zp[n] <= r) {
          low = true;
          break;
        }
      }
      if (low) {
        heap.push(zp[c], c);
        continue;
      }
      for (int k = 0; k < 8; ++k) {
        const std::int32_t n = c + off[k];
        if (closed[n]) continue;
        closed[n] = 1;
        trace.push_back(n);
      }
    }
    if (work > (1u << 18)) {
      work = 0;
      check(ctx);
    }
  }
  P.copy_back(g, z);
}

template <bool kEpsilon>
void breach_impl(const FlowGrid& g, std::span<float> z, const Outlets& outlets, const ExecContext* ctx) {
  Padded P(g, z);
  float* zp = P.z.data();
  std::uint8_t* closed = P.closed.data();
  const std::int32_t* off = P.off;
  std::vector<std::uint8_t> is_outlet(P.z.size(), 0);
  MinHeap heap;
  for_each_outlet(g, outlets, [&](int i, int j) {
    const std::int32_t c = P.p(i, j);
    closed[c] = 1;
    is_outlet[c] = 1;
    heap.push(zp[c], c);
  });
  std::vector<std::int32_t> backlink(P.z.size(), -1);
  std::size_t work = 0;
  while (!heap.empty()) {
    const Entry e = heap.pop();
    const std::int32_t c = e.c;
    if (!is_outlet[c]) {
      bool pit = true;
      for (int k = 0; k < 8 && pit; ++k) pit = !(zp[c + off[k]] < zp[c]);
      if (pit) {
        float target = kEpsilon ? std::nextafter(zp[c], -kInf) : zp[c];
        for (std::int32_t b = backlink[c]; b >= 0; b = backlink[b]) {
          if (zp[b] <= target) break;
          zp[b] = target;
          if (kEpsilon) target = std::nextafter(target, -kInf);
        }
      }
    }
    for (int k = 0; k < 8; ++k) {
      const std::int32_t n = c + off[k];
      if (closed[n]) continue;
      closed[n] = 1;
      backlink[n] = c;
      heap.push(zp[n], n);
    }
    if (++work > (1u << 16)) {
      work = 0;
      check(ctx);
    }
  }
  P.copy_back(g, z);
}

struct NeighbourTable {
  std::int32_t off[8];
  double inv_dist[8];
  explicit NeighbourTable(const FlowGrid& g) {
    for (int k = 0; k < 8; ++k) {
      off[k] = g.offset(k);
      inv_dist[k] = 1.0 / g.distance(k);
    }
  }
};

// Steepest strictly descending neighbour of (i, j), kNoDirection if none.
template <bool kInterior>
inline int steepest(const FlowGrid& g, const NeighbourTable& t, const float* z, int i, int j, double* best_slope) {
  const std::int32_t c = g.index(i, j);
  const double zc = z[c];
  double best = 0.0;
  int bk = kNoDirection;
  for (int k = 0; k < 8; ++k) {
    if (!kInterior && !g.inside(i + kDi[k], j + kDj[k])) continue;
    const double s = (zc - z[c + t.off[k]]) * t.inv_dist[k];
    if (s > best) {
      best = s;
      bk = k;
    }
  }
  if (best_slope) *best_slope = best;
  return bk;
}

double cell_weight(std::span<const float> w, std::size_t c, double area) { return w.empty() ? area : w[c]; }

// Dispersive receivers of (i, j) for MFD and D-infinity; returns their count.
template <bool kInterior>
int route_cell(const FlowGrid& g, const NeighbourTable& t, const float* z, int i, int j, const RoutingOptions& opt,
               int nbr[8], double frac[8]) {
  if (opt.outlets.is_outlet(g, i, j)) return 0;
  const std::int32_t c = g.index(i, j);
  const double zc = z[c];
  if (opt.method == FlowMethod::MFD) {
    // Weights (tan beta / max tan beta)^p: the largest is 1, so no underflow for large exponents.
    int n = 0;
    double smax = 0.0;
    for (int k = 0; k < 8; ++k) {
      if (!kInterior && !g.inside(i + kDi[k], j + kDj[k])) continue;
      const double s = (zc - z[c + t.off[k]]) * t.inv_dist[k];
      if (s <= 0.0) continue;
      nbr[n] = k;
      frac[n] = s;
      smax = std::max(smax, s);
      ++n;
    }
    if (n == 0) return 0;
    double sum = 0.0;
    for (int m = 0; m < n; ++m) {
      frac[m] = opt.exponent == 1.0 ? frac[m] / smax : std::pow(frac[m] / smax, opt.exponent);
      sum += frac[m];
    }
    const double inv = 1.0 / sum;
    for (int m = 0; m < n; ++m) frac[m] *= inv;
    return n;
  }
  if (opt.method == FlowMethod::DInfinity) {
    // Facets (cardinal k1, diagonal k2); Tarboton 1997.
    static constexpr int kFacets[8][2] = {{0, 1}, {2, 1}, {2, 3}, {4, 3}, {4, 5}, {6, 5}, {6, 7}, {0, 7}};
    double best = 0.0, best_r = 0.0, best_rmax = 1.0;
    int bf = -1;
    for (int f = 0; f < 8; ++f) {
      const int k1 = kFacets[f][0], k2 = kFacets[f][1];
      if (!kInterior && (!g.inside(i + kDi[k1], j + kDj[k1]) || !g.inside(i + kDi[k2], j + kDj[k2]))) continue;
      const double d1 = (k1 & 2) ? g.dy : g.dx;
      const double d2 = (k1 & 2) ? g.dx : g.dy;
      const double e1 = z[c + t.off[k1]], e2 = z[c + t.off[k2]];
      const double s1 = (zc - e1) / d1, s2 = (e1 - e2) / d2;
      const double rmax = std::atan2(d2, d1);
      double r = std::atan2(s2, s1), s;
      if (r < 0.0) {
        r = 0.0;
        s = s1;
      } else if (r > rmax) {
        r = rmax;
        s = (zc - e2) / std::hypot(d1, d2);
      } else {
        s = std::hypot(s1, s2);
      }
      if (s > best) {
        best = s;
        bf = f;
        best_r = r;
        best_rmax = rmax;
      }
    }
    if (bf < 0) return 0;
    const double p2 = best_r / best_rmax;
    int n = 0;
    if (p2 < 1.0) {
      nbr[n] = kFacets[bf][0];
      frac[n++] = 1.0 - p2;
    }
    if (p2 > 0.0) {
      nbr[n] = kFacets[bf][1];
      frac[n++] = p2;
    }
    return n;
  }
  const int k = steepest<kInterior>(g, t, z, i, j, nullptr);
  if (k == kNoDirection) return 0;
  nbr[0] = k;
  frac[0] = 1.0;
  return 1;
}

bool interior_cell(const FlowGrid& g, int i, int j) { return i > 0 && j > 0 && i < g.nx - 1 && j < g.ny - 1; }

}  // namespace

void fill_depressions(const FlowGrid& g, std::span<float> z, FlatMode mode, const Outlets& outlets,
                      const ExecContext* ctx) {
  if (g.size() == 0) return;
  if (mode == FlatMode::Epsilon)
    fill_impl<true>(g, z, outlets, ctx);
  else
    fill_impl<false>(g, z, outlets, ctx);
}

void breach_depressions(const FlowGrid& g, std::span<float> z, FlatMode mode, const Outlets& outlets,
                        const ExecContext* ctx) {
  if (g.size() == 0) return;
  if (mode == FlatMode::Epsilon)
    breach_impl<true>(g, z, outlets, ctx);
  else
    breach_impl<false>(g, z, outlets, ctx);
}

D8Flow d8_flow(const FlowGrid& g, std::span<const float> z, const Outlets& outlets, const ExecContext* ctx) {
  D8Flow f;
  const std::size_t n = g.size();
  f.receiver.resize(n);
  f.direction.resize(n);
  f.donors.resize(n);
  const NeighbourTable t(g);
  const float* zz = z.data();
  for_each_row(ctx, g.ny, [&](int j) {
    for (int i = 0; i < g.nx; ++i) {
      const std::int32_t c = g.index(i, j);
      int k;
      if (outlets.is_outlet(g, i, j))
        k = kNoDirection;
      else if (interior_cell(g, i, j))
        k = steepest<true>(g, t, zz, i, j, nullptr);
      else
        k = steepest<false>(g, t, zz, i, j, nullptr);
      f.direction[c] = static_cast<std::uint8_t>(k);
      f.receiver[c] = k == kNoDirection ? c : c + t.off[k];
    }
  }, 0.0, 0.5);
  for_each_row(ctx, g.ny, [&](int j) {
    for (int i = 0; i < g.nx; ++i) {
      const std::int32_t c = g.index(i, j);
      std::uint8_t m = 0;
      if (interior_cell(g, i, j)) {
        for (int k = 0; k < 8; ++k)
          if (f.direction[c + t.off[k]] == opposite(k)) m |= static_cast<std::uint8_t>(1u << k);
      } else {
        for (int k = 0; k < 8; ++k)
          if (g.inside(i + kDi[k], j + kDj[k]) && f.direction[c + t.off[k]] == opposite(k))
            m |= static_cast<std::uint8_t>(1u << k);
      }
      f.donors[c] = m;
    }
  }, 0.5, 1.0);
  return f;
}

std::vector<std::int32_t> stack_order(const FlowGrid& g, const D8Flow& f) {
  const std::int32_t n = static_cast<std::int32_t>(f.receiver.size());
  std::vector<std::int32_t> order;
  order.reserve(static_cast<std::size_t>(n));
  std::vector<std::int32_t> st;
  std::int32_t off[8];
  for (int k = 0; k < 8; ++k) off[k] = g.offset(k);
  for (std::int32_t c = 0; c < n; ++c) {
    if (f.receiver[c] != c) continue;
    st.push_back(c);
    while (!st.empty()) {
      const std::int32_t x = st.back();
      st.pop_back();
      order.push_back(x);
      for (unsigned m = f.donors[x]; m; m &= m - 1) st.push_back(x + off[std::countr_zero(m)]);
    }
  }
  return order;
}

std::vector<std::int32_t> basin_labels(const D8Flow& f, std::span<const std::int32_t> order, int* basin_count) {
  std::vector<std::int32_t> label(f.receiver.size(), -1);
  std::int32_t count = 0;
  for (std::int32_t x : order) {
    const std::int32_t r = f.receiver[x];
    label[x] = r == x ? count++ : label[r];
  }
  if (basin_count) *basin_count = count;
  return label;
}

std::vector<double> accumulate_d8(const FlowGrid& g, const D8Flow& f, std::span<const float> weight,
                                  const ExecContext* ctx) {
  const std::size_t n = f.receiver.size();
  std::vector<double> acc(n);
  std::vector<std::uint8_t> remaining(n);
  for (std::size_t c = 0; c < n; ++c) remaining[c] = static_cast<std::uint8_t>(std::popcount(f.donors[c]));
  std::int32_t off[8];
  for (int k = 0; k < 8; ++k) off[k] = g.offset(k);
  const double area = g.cell_area();
  const std::int32_t* rec = f.receiver.data();
  const std::uint8_t* donors = f.donors.data();
  double* a = acc.data();
  // acc of a cell whose donors are all done: its own weight plus the donors in neighbour order, so the sum
  // does not depend on which thread finished last.
  auto pull = [&](std::int32_t c) {
    double s = cell_weight(weight, static_cast<std::size_t>(c), area);
    for (unsigned m = donors[c]; m; m &= m - 1) s += a[c + off[std::countr_zero(m)]];
    a[c] = s;
  };
  const bool parallel = tbb::this_task_arena::max_concurrency() > 1 && n >= (1u << 16);
  const int rows_per_chunk = 32;
  const int chunks = (g.ny + rows_per_chunk - 1) / rows_per_chunk;
  auto run_chunk = [&](int chunk, auto atomic_tag) {
    constexpr bool kAtomic = decltype(atomic_tag)::value;
    const std::int32_t begin = g.index(0, chunk * rows_per_chunk);
    const std::int32_t end = g.index(0, std::min(g.ny, (chunk + 1) * rows_per_chunk));
    for (std::int32_t c = begin; c < end; ++c) {
      if (donors[c] != 0) continue;
      pull(c);
      std::int32_t x = c;
      for (;;) {
        const std::int32_t r = rec[x];
        if (r == x) break;
        if constexpr (kAtomic) {
          if (std::atomic_ref<std::uint8_t>(remaining[r]).fetch_sub(1, std::memory_order_acq_rel) != 1) break;
        } else {
          if (--remaining[r] != 0) break;
        }
        pull(r);
        x = r;
      }
    }
  };
  if (parallel) {
    std::atomic<int> done{0};
    tbb::parallel_for(tbb::blocked_range<int>(0, chunks, 1), [&](const tbb::blocked_range<int>& r) {
      check(ctx);
      for (int ch = r.begin(); ch != r.end(); ++ch) run_chunk(ch, std::true_type{});
      const int d = done.fetch_add(static_cast<int>(r.size())) + static_cast<int>(r.size());
      if (ctx) ctx->progress(static_cast<double>(d) / chunks);
    });
  } else {
    for (int ch = 0; ch < chunks; ++ch) {
      if ((ch & 7) == 0) check(ctx);
      run_chunk(ch, std::false_type{});
    }
  }
  check(ctx);
  return acc;
}

int flow_proportions(const FlowGrid& g, std::span<const float> z, int i, int j, const RoutingOptions& opt,
                     int nbr[8], double frac[8]) {
  const NeighbourTable t(g);
  return route_cell<false>(g, t, z.data(), i, j, opt, nbr, frac);
}

std::vector<double> accumulate(const FlowGrid& g, std::span<const float> z, const RoutingOptions& opt,
                               std::span<const float> weight, const ExecContext* ctx) {
  if (opt.method == FlowMethod::D8) return accumulate_d8(g, d8_flow(g, z, opt.outlets, ctx), weight, ctx);
  const std::size_t n = g.size();
  const NeighbourTable t(g);
  const float* zz = z.data();
  // D-infinity: receivers stored (two neighbours and a split); MFD: recomputed when pushed.
  std::vector<std::uint8_t> dk1, dk2;
  std::vector<float> dfrac;
  const bool dinf = opt.method == FlowMethod::DInfinity;
  if (dinf) {
    dk1.assign(n, kNoDirection);
    dk2.assign(n, kNoDirection);
    dfrac.assign(n, 0.0f);
    for_each_row(ctx, g.ny, [&](int j) {
      for (int i = 0; i < g.nx; ++i) {
        int nb[8];
        double fr[8];
        const int cnt = interior_cell(g, i, j) ? route_cell<true>(g, t, zz, i, j, opt, nb, fr)
                                               : route_cell<false>(g, t, zz, i, j, opt, nb, fr);
        const std::int32_t c = g.index(i, j);
        if (cnt >= 1) {
          dk1[c] = static_cast<std::uint8_t>(nb[0]);
          dfrac[c] = static_cast<float>(fr[0]);
        }
        if (cnt == 2) dk2[c] = static_cast<std::uint8_t>(nb[1]);
        if (cnt == 1) dfrac[c] = 1.0f;
      }
    }, 0.0, 0.3);
  }
  // Number of neighbours that send flow to each cell.
  std::vector<std::uint8_t> remaining(n);
  for_each_row(ctx, g.ny, [&](int j) {
    for (int i = 0; i < g.nx; ++i) {
      const std::int32_t c = g.index(i, j);
      int cnt = 0;
      for (int k = 0; k < 8; ++k) {
        const int ii = i + kDi[k], jj = j + kDj[k];
        if (!g.inside(ii, jj)) continue;
        const std::int32_t m = c + t.off[k];
        if (dinf) {
          cnt += (dk1[m] == opposite(k)) + (dk2[m] == opposite(k));
        } else {
          cnt += zz[m] > zz[c] && !opt.outlets.is_outlet(g, ii, jj);
        }
      }
      remaining[c] = static_cast<std::uint8_t>(cnt);
    }
  }, 0.3, 0.5);
  std::vector<double> acc(n);
  const double area = g.cell_area();
  for (std::size_t c = 0; c < n; ++c) acc[c] = cell_weight(weight, c, area);
  std::vector<std::int32_t> st;
  constexpr std::uint8_t kDone = 0xFF;
  std::size_t work = 0;
  for (std::int32_t c0 = 0; c0 < static_cast<std::int32_t>(n); ++c0) {
    if (remaining[c0] != 0) continue;
    remaining[c0] = kDone;
    st.push_back(c0);
    while (!st.empty()) {
      const std::int32_t x = st.back();
      st.pop_back();
      const double ax = acc[x];
      auto give = [&](int k, double fr) {
        const std::int32_t m = x + t.off[k];
        acc[m] += ax * fr;
        if (--remaining[m] == 0) {
          remaining[m] = kDone;
          st.push_back(m);
        }
      };
      if (dinf) {
        if (dk1[x] != kNoDirection) give(dk1[x], dk2[x] != kNoDirection ? dfrac[x] : 1.0);
        if (dk2[x] != kNoDirection) give(dk2[x], 1.0 - static_cast<double>(dfrac[x]));
      } else {
        const int i = g.column(x), j = g.row(x);
        int nb[8];
        double fr[8];
        const int cnt = interior_cell(g, i, j) ? route_cell<true>(g, t, zz, i, j, opt, nb, fr)
                                               : route_cell<false>(g, t, zz, i, j, opt, nb, fr);
        for (int m = 0; m < cnt; ++m) give(nb[m], fr[m]);
      }
    }
    if (++work > (1u << 16)) {
      work = 0;
      check(ctx);
    }
  }
  return acc;
}

std::vector<float> steepest_slope(const FlowGrid& g, std::span<const float> z, const ExecContext* ctx) {
  std::vector<float> s(g.size());
  const NeighbourTable t(g);
  for_each_row(ctx, g.ny, [&](int j) {
    for (int i = 0; i < g.nx; ++i) {
      double best = 0.0;
      if (interior_cell(g, i, j))
        steepest<true>(g, t, z.data(), i, j, &best);
      else
        steepest<false>(g, t, z.data(), i, j, &best);
      s[static_cast<std::size_t>(g.index(i, j))] = static_cast<float>(best);
    }
  });
  return s;
}

}  // namespace orogen::hydrology
