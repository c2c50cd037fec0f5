#include "nodes/hydrology/flow_routing.h"

#include "nodes/hydrology/breach_rule.h"
#include "nodes/hydrology/flow_shares.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cstring>
#include <functional>
#include <limits>
#include <stdexcept>

#include <emmintrin.h>
#include <xmmintrin.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/task_arena.h>

#include "graph/exec_context.h"
#include "nodes/common/huge_page_buffer.h"
#include "nodes/common/cancellable_rows.h"

namespace orogen::hydrology {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

void check(const ExecContext* ctx) {
  if (ctx) ctx->check_cancelled();
}

// Smallest float above v (v finite): one ulp up, without a libm call.
inline float next_up(float v) {
  if (v == 0.0f) return std::numeric_limits<float>::denorm_min();
  std::uint32_t b = std::bit_cast<std::uint32_t>(v);
  b += v > 0.0f ? 1u : static_cast<std::uint32_t>(-1);
  return std::bit_cast<float>(b);
}
inline float next_down(float v) { return -next_up(-v); }

// Order-preserving unsigned image of a float (for finite values and infinities).
inline std::uint32_t ordered_bits(float v) {
  const std::uint32_t b = std::bit_cast<std::uint32_t>(v);
  return (b & 0x80000000u) ? ~b : (b | 0x80000000u);
}

struct Entry {
  float z;
  std::int32_t c;
};

// Monotone priority queue of (height, cell) pairs, smallest height first: a radix heap (Ahuja, Mehlhorn,
// Orlin & Tarjan 1990) with radix 256 over the 32-bit ordered height bits, the cell riding along in the low half
// of a 64-bit item. Priority-Flood only pushes heights at or above the last one popped, which is what a radix
// heap requires. An item sits at level l (0..3) when its key first differs from `last_` in byte l, in the bucket
// of its byte l; level 0 holds keys that differ from last_ in the low byte only, so a level-0 bucket holds one
// key. When level 0 is empty, the smallest bucket of the lowest nonempty level is spread over the levels below
// it, around its smallest key (each bucket keeps its minimum): an item moves down at most three times (the
// binary radix heap moved each about ten times on 4096^2 fBm, 8% of the fill's time). Its buckets are plain
// arrays, much cheaper than a binary heap's sift on large queues. Equal heights leave in a fixed (LIFO) order,
// so the result is deterministic. peek_cell() settles the next minimum early (so its neighbourhood can be
// prefetched); heights pushed after that but below it wait in a small binary heap that is served first.
class MinHeap {
 public:
  MinHeap() {
    for (auto& level : min_) std::fill(std::begin(level), std::end(level), kNone);
  }
  void push(float z, std::int32_t c) {
    const std::uint32_t key = ordered_bits(z);
    const std::uint64_t item = (static_cast<std::uint64_t>(key) << 32) | static_cast<std::uint32_t>(c);
    if (key < last_) {
      early_.push_back(item);
      std::push_heap(early_.begin(), early_.end(), std::greater<>{});
      return;
    }
    add(item);
    ++size_;
  }
  Entry pop() {
    std::uint64_t item;
    if (!early_.empty()) {
      std::pop_heap(early_.begin(), early_.end(), std::greater<>{});
      item = early_.back();
      early_.pop_back();
    } else {
      settle();
      auto& b = buckets_[0][current_];
      item = b.back();
      b.pop_back();
      if (b.empty()) nonempty_[0][current_ >> 6] &= ~(1ull << (current_ & 63));
      --size_;
    }
    const std::uint32_t zb = static_cast<std::uint32_t>(item >> 32);
    const std::uint32_t bits = (zb & 0x80000000u) ? (zb & 0x7FFFFFFFu) : ~zb;
    return {std::bit_cast<float>(bits), static_cast<std::int32_t>(static_cast<std::uint32_t>(item))};
  }
  // The height pop() will return next (not empty()).
  float peek_z() {
    std::uint64_t item;
    if (!early_.empty()) {
      item = early_.front();
    } else {
      settle();
      item = buckets_[0][current_].back();
    }
    const std::uint32_t zb = static_cast<std::uint32_t>(item >> 32);
    return std::bit_cast<float>((zb & 0x80000000u) ? (zb & 0x7FFFFFFFu) : ~zb);
  }
  // The cell pop() will return next (-1 if empty), so its neighbourhood can be prefetched.
  std::int32_t peek_cell() {
    if (!early_.empty()) return static_cast<std::int32_t>(static_cast<std::uint32_t>(early_.front()));
    if (size_ == 0) return -1;
    settle();
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(buckets_[0][current_].back()));
  }
  bool empty() const { return size_ == 0 && early_.empty(); }

 private:
  static constexpr std::uint64_t kNone = ~std::uint64_t{0};
  // First set bit of a 256-bit mask, or -1.
  static int first(const std::uint64_t* mask) {
    for (int w = 0; w < 4; ++w)
      if (mask[w]) return w * 64 + std::countr_zero(mask[w]);
    return -1;
  }
  void add(std::uint64_t item) {
    const std::uint32_t key = static_cast<std::uint32_t>(item >> 32);
    const int level = (std::bit_width((key ^ last_) | 1u) - 1) >> 3;
    const int b = static_cast<int>(key >> (8 * level) & 0xFFu);
    buckets_[level][b].push_back(item);
    min_[level][b] = std::min(min_[level][b], item);
    nonempty_[level][b >> 6] |= 1ull << (b & 63);
  }
  // Makes level 0 nonempty (size_ > 0) and current_ its first bucket.
  void settle() {
    for (;;) {
      int b = first(nonempty_[0]);
      if (b >= 0) {
        current_ = b;
        return;
      }
      int level = 1;
      while ((b = first(nonempty_[level])) < 0) ++level;
      auto& v = buckets_[level][b];
      last_ = static_cast<std::uint32_t>(min_[level][b] >> 32);
      min_[level][b] = kNone;
      nonempty_[level][b >> 6] &= ~(1ull << (b & 63));
      for (std::uint64_t item : v) add(item);
      v.clear();
    }
  }
  std::vector<std::uint64_t> buckets_[4][256];
  std::uint64_t min_[4][256];          // smallest item of each bucket (level 0: unused)
  std::uint64_t nonempty_[4][4] = {};  // bit b of level l: bucket b has items
  std::vector<std::uint64_t> early_;   // min-heap of items below last_
  std::uint32_t last_ = 0;
  int current_ = 0;  // level-0 bucket of the minimum, after settle()
  std::size_t size_ = 0;
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
    for (int j = 0; j < g.ny; ++j)
      std::copy_n(z.data() + p(0, j), g.nx, dst.data() + static_cast<std::size_t>(j) * g.nx);
  }
};

// Every outlet in increasing cell index (without a mask only the border is visited).
template <class Fn>
void for_each_outlet(const FlowGrid& g, const Outlets& outlets, Fn&& fn) {
  if (!outlets.mask.empty()) {
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i)
        if (outlets.is_outlet(g, i, j)) fn(i, j);
    return;
  }
  if (!outlets.border) return;
  for (int j = 0; j < g.ny; ++j) {
    if (j == 0 || j == g.ny - 1) {
      for (int i = 0; i < g.nx; ++i) fn(i, j);
    } else {
      fn(0, j);
      if (g.nx > 1) fn(g.nx - 1, j);
    }
  }
}

struct QueuedCell {
  std::int32_t c;  // padded index
  float z;         // its final height
};

// One bit per cell of a padded grid: the closed flags of Priority-Flood. 4096^2 cells take 2 MB, which stays in
// the L2 cache, where a flag in the height array would bring its cache line in for every closed test.
inline void set_bit(std::uint8_t* bits, std::int32_t i) { bits[i >> 3] |= static_cast<std::uint8_t>(1u << (i & 7)); }
// Bits i, i + 1, i + 2 (one unaligned 4-byte read; the array has 4 spare bytes).
inline unsigned three_bits(const std::uint8_t* bits, std::int32_t i) {
  std::uint32_t v;
  std::memcpy(&v, bits + (i >> 3), sizeof v);
  return v >> (i & 7) & 7u;
}
// Clears bits [from, to).
void clear_bits(std::uint8_t* bits, std::int32_t from, std::int32_t to) {
  while (from < to && (from & 7)) bits[from >> 3] &= static_cast<std::uint8_t>(~(1u << (from & 7))), ++from;
  while (from < to && (to & 7)) --to, bits[to >> 3] &= static_cast<std::uint8_t>(~(1u << (to & 7)));
  if (from < to) std::fill(bits + (from >> 3), bits + (to >> 3), std::uint8_t{0});
}

// Priority-Flood (Barnes et al. 2014) with the depression and slope queues of Zhou et al. 2016. Profiled on
// 4096^2 fBm: the time goes into the neighbour tests (two unpredictable branches per neighbour: closed?
// lower?), the priority queue and the memory behind them, as the queues jump between distant rows. So:
// - one working array `zw` (padded, in huge pages) holds the heights and is raised in place, and the closed
//   flags are bits in a second array small enough for the L2 cache; the 8 neighbours' masks (open; open and
//   at or below the level) come from three 4-float SSE compares and three bit reads, with no branch per
//   neighbour; neighbours are then visited by iterating the set bits;
// - a slope cell goes to the priority queue when it has a lower open neighbour, but by the time it is popped
//   that neighbour has nearly always been closed from elsewhere: the closed bits show it without touching
//   the heights, both before the push (after the climb) and at the pop;
// - the heights travel in the queues; 32-bit radix heap keys; outlets enumerated along the border only.
//
// Epsilon computes the least surface e with e = z at the outlets and e(n) = max(z(n), min over the 8 neighbours
// m of next_up(e(m))) elsewhere: a shortest-path fixed point with the monotone edge map x -> max(z(n),
// next_up(x)), unique, so it depends on the heights alone and not on the order ties are visited in (which is
// what lets tiles reproduce it, nodes/hydrology/tile_fill.h). Dijkstra computes it exactly when cells are
// expanded in non-decreasing order of their value: a raised (pit) cell enters the FIFO at next_up(value of the
// cell expanded), and expanded values never decrease, so the FIFO is sorted and the next cell is the smaller
// of its front and the priority queue's top. Slope cells are final at their own height whenever they are
// found (max(z(n), next_up(x)) = z(n) for every x whose next_up is at most z(n)), so they climb in any order.
// Flat needs no interleaving: every pit cell has the level of the cell popped, the queue's minimum.
template <bool kEpsilon>
void fill_impl(const FlowGrid& g, std::span<float> z, const Outlets& outlets, const ExecContext* ctx) {
  const std::int32_t W = g.nx + 2;
  const std::size_t cells = static_cast<std::size_t>(W) * static_cast<std::size_t>(g.ny + 2);
  auto p = [W](int i, int j) { return (j + 1) * W + (i + 1); };
  // Four spare floats (bytes) at the end for the last row's 4-wide loads (bit reads).
  HugePageBuffer<float> zw_store(cells + 4);
  HugePageBuffer<std::uint8_t> closed_store(cells / 8 + 5);
  float* __restrict zw = zw_store.data();
  std::uint8_t* __restrict closed = closed_store.data();
  std::fill_n(closed, closed_store.size(), std::uint8_t{0xFF});
  std::fill_n(zw, p(0, 0), kInf);
  for (int j = 0; j < g.ny; ++j) {
    std::copy_n(z.data() + static_cast<std::size_t>(j) * static_cast<std::size_t>(g.nx), g.nx, zw + p(0, j));
    zw[p(g.nx, j)] = kInf;      // right frame
    zw[p(g.nx + 1, j)] = kInf;  // left frame of the next row
    clear_bits(closed, p(0, j), p(g.nx, j));
  }
  std::fill(zw + p(g.nx, g.ny - 1), zw + cells + 4, kInf);
  auto step = [](float v) { return kEpsilon ? next_up(v) : v; };
  MinHeap heap;
  for_each_outlet(g, outlets, [&](int i, int j) {
    const std::int32_t c = p(i, j);
    heap.push(zw[c], c);
    set_bit(closed, c);
  });
  // pit: depression cells to expand; trace: slope cells to climb from; spill: slope cells with a lower open
  // neighbour, for the priority queue.
  std::vector<QueuedCell> pit, trace, spill;
  pit.reserve(1024);
  trace.reserve(1024);
  // Bit b of a neighbour mask is the neighbour (b % 3 - 1, b / 3 - 1), in memory order; bit 4 (the cell
  // itself, closed) is never set.
  const std::int32_t noff[9] = {-W - 1, -W, -W + 1, -1, 0, 1, W - 1, W, W + 1};
  struct Masks {
    unsigned open, low;  // open: not closed yet; low: open and at or below the level
  };
  auto open_around = [closed, W](std::int32_t c) -> unsigned {
    return ~(three_bits(closed, c - W - 1) | three_bits(closed, c - 1) << 3 | three_bits(closed, c + W - 1) << 6) &
           0x1EFu;
  };
  auto masks = [zw, W, open_around](std::int32_t c, float r) -> Masks {
    const __m128 rv = _mm_set1_ps(r);
    const __m128 a = _mm_loadu_ps(zw + c - W - 1), b = _mm_loadu_ps(zw + c - 1), d = _mm_loadu_ps(zw + c + W - 1);
    const unsigned le = (static_cast<unsigned>(_mm_movemask_ps(_mm_cmple_ps(a, rv))) & 7u) |
                        (static_cast<unsigned>(_mm_movemask_ps(_mm_cmple_ps(b, rv))) & 5u) << 3 |
                        (static_cast<unsigned>(_mm_movemask_ps(_mm_cmple_ps(d, rv))) & 7u) << 6;
    const unsigned open = open_around(c);
    return {open, le & open};
  };
  // Closes the open neighbours of c: those at or below r join the depression at level r, the others are slope
  // cells (final height). Epsilon: trace_min is the lowest slope cell not climbed from yet.
  float trace_min = kInf;
  auto expand_pit = [&](std::int32_t c, float r) {
    const Masks m = masks(c, r);
    for (unsigned x = m.open; x; x &= x - 1) {
      const int b = std::countr_zero(x);
      const std::int32_t n = c + noff[b];
      const float zn = zw[n];
      set_bit(closed, n);
      if (m.low >> b & 1) {
        zw[n] = r;
        pit.push_back({n, r});
      } else {
        trace.push_back({n, zn});
        if constexpr (kEpsilon) trace_min = std::min(trace_min, zn);
      }
    }
  };
  // Slope cells: their height is final; climb while no open neighbour could be lower (a potential spill into
  // another depression), otherwise hand the cell to the priority queue. Breadth first: the front stays compact,
  // so half as many cells end up in the priority queue as with a stack. A fifth of the handed cells have had all
  // their lower neighbours closed by the rest of the climb: they need not wait in the queue.
  auto climb = [&] {
    for (std::size_t th = 0; th < trace.size(); ++th) {
      const QueuedCell q = trace[th];
      const Masks m = masks(q.c, step(q.z));
      if (m.low) {
        spill.push_back(q);
        continue;
      }
      for (unsigned x = m.open; x; x &= x - 1) {
        const std::int32_t n = q.c + noff[std::countr_zero(x)];
        trace.push_back({n, zw[n]});
        set_bit(closed, n);
      }
    }
    const std::size_t climbed = trace.size();
    trace.clear();
    float lowest = kInf;  // of the cells pushed
    for (const QueuedCell& q : spill)
      if (open_around(q.c)) heap.push(q.z, q.c), lowest = std::min(lowest, q.z);
    spill.clear();
    return std::make_pair(climbed, lowest);
  };
  std::size_t work = 0, done = 0;
  auto report = [&] {
    if (work > (1u << 18)) {
      done += work;
      work = 0;
      check(ctx);
      if (ctx) ctx->progress(std::min(1.0, static_cast<double>(done) / static_cast<double>(g.size())));
    }
  };
  if constexpr (kEpsilon) {
    std::size_t head = 0;  // front of the pit FIFO
    // The heap's minimum (kInf when empty): found after a pop, lowered by what the climbs push.
    float top = kInf;
    for (;;) {
      // The pit cells no higher than the heap's minimum, in FIFO order. The slope cells found meanwhile are
      // climbed from (their spills pushed) before the first pit cell above them: as late as that, most of their
      // lower neighbours have been closed by the depression, so few of them wait in the heap for nothing.
      for (;;) {
        while (head < pit.size() && pit[head].z <= top && pit[head].z <= trace_min) {
          const QueuedCell q = pit[head++];
          expand_pit(q.c, next_up(q.z));
          ++work;
        }
        if (trace.empty()) break;
        const auto [climbed, lowest] = climb();
        work += climbed;
        top = std::min(top, lowest);
        trace_min = kInf;
        if (!(head < pit.size() && pit[head].z <= top)) break;
      }
      if (head == pit.size()) {
        pit.clear(), head = 0;
      } else if (head > (1u << 16) && head * 2 > pit.size()) {
        // A long FIFO whose front has moved far: drop the expanded part.
        pit.erase(pit.begin(), pit.begin() + static_cast<std::ptrdiff_t>(head)), head = 0;
      }
      report();
      if (heap.empty()) {
        if (head == pit.size()) break;
        top = kInf;
        continue;
      }
      const Entry e = heap.pop();
      if (const std::int32_t nx = heap.peek_cell(); nx >= 0) {
        for (std::int32_t r : {nx - W, nx, nx + W}) __builtin_prefetch(closed + ((r - 1) >> 3));
      }
      top = heap.empty() ? kInf : heap.peek_z();
      // Nearly all popped cells (96% on fBm) are stale: the lower neighbour that sent them to the queue has
      // been closed since. The bits tell without reading their heights, which are far from cache.
      if (!open_around(e.c)) continue;
      expand_pit(e.c, next_up(e.z));
      ++work;
    }
  } else {
    while (!heap.empty()) {
      const Entry e = heap.pop();
      // Popped cells are scattered over the grid: fetch the next one's closed bits while this one works.
      if (const std::int32_t nx = heap.peek_cell(); nx >= 0) {
        for (std::int32_t r : {nx - W, nx, nx + W}) __builtin_prefetch(closed + ((r - 1) >> 3));
      }
      // Nearly all popped cells (96% on fBm) are stale: the lower neighbour that sent them to the queue has
      // been closed since. The bits tell without reading their heights, which are far from cache.
      if (!open_around(e.c)) continue;
      expand_pit(e.c, e.z);
      // Depression cells: breadth first at the spill level.
      for (std::size_t head = 0; head < pit.size(); ++head) expand_pit(pit[head].c, pit[head].z);
      work += pit.size();
      pit.clear();
      work += climb().first;
      report();
    }
  }
  for (int j = 0; j < g.ny; ++j)
    std::copy_n(zw + p(0, j), g.nx, z.data() + static_cast<std::size_t>(j) * static_cast<std::size_t>(g.nx));
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

// The MFD weight (s / smax)^p of a receiver of slope s, before normalisation, in single precision (expf/logf are
// several times cheaper than pow; the proportions are normalised, so they still sum to 1).
inline double mfd_weight(double s, double smax, double exponent) {
  const float t = static_cast<float>(s / smax);
  return exponent == 1.0 ? t : std::exp(static_cast<float>(exponent) * std::log(t));
}

// Whether cell c = (i, j) is an outlet of `opt` (it sends nothing). Interior cells are never border outlets: only
// the mask can make them one.
template <bool kInterior>
bool routed_outlet(const FlowGrid& g, const RoutingOptions& opt, std::int32_t c, int i, int j) {
  return kInterior ? (!opt.outlets.mask.empty() && opt.outlets.mask[static_cast<std::size_t>(c)] != 0)
                   : opt.outlets.is_outlet(g, i, j);
}

// MFD's slope from cell c, of height zc, down to its neighbour k (height per unit distance); k receives where it is
// not <= 0 (route_cell and mfd_receivers decide alike, NaN included).
inline double mfd_slope(const NeighbourTable& t, const float* z, std::int32_t c, double zc, int k) {
  return (zc - z[c + t.off[k]]) * t.inv_dist[k];
}

// Dispersive receivers of (i, j) for MFD and D-infinity; returns their count. MFD: `weights` (optional) receives the
// weights themselves, floats (mfd_weight's), so that weights[m] times 1 / their sum (added in order) is frac[m] bit
// for bit.
template <bool kInterior>
int route_cell(const FlowGrid& g, const NeighbourTable& t, const float* z, int i, int j, const RoutingOptions& opt,
               int nbr[8], double frac[8], float* weights = nullptr) {
  const std::int32_t c = g.index(i, j);
  if (routed_outlet<kInterior>(g, opt, c, i, j)) return 0;
  const double zc = z[c];
  if (opt.method == FlowMethod::MFD) {
    // Weights (tan beta / max tan beta)^p: the largest is 1, so no underflow for large exponents.
    int n = 0;
    double smax = 0.0;
    for (int k = 0; k < 8; ++k) {
      if (!kInterior && !g.inside(i + kDi[k], j + kDj[k])) continue;
      const double s = mfd_slope(t, z, c, zc, k);
      if (s <= 0.0) continue;
      nbr[n] = k;
      frac[n] = s;
      smax = std::max(smax, s);
      ++n;
    }
    if (n == 0) return 0;
    double sum = 0.0;
    for (int m = 0; m < n; ++m) {
      frac[m] = mfd_weight(frac[m], smax, opt.exponent);
      sum += frac[m];
    }
    const double inv = 1.0 / sum;
    if (weights)
      for (int m = 0; m < n; ++m) weights[m] = static_cast<float>(frac[m]);  // exact: mfd_weight is a float
    for (int m = 0; m < n; ++m) frac[m] *= inv;
    return n;
  }
  if (opt.method == FlowMethod::DInfinity) {
    // Facets (cardinal k1, diagonal k2); Tarboton 1997.
    static constexpr int kFacets[8][2] = {{0, 1}, {2, 1}, {2, 3}, {4, 3}, {4, 5}, {6, 5}, {6, 7}, {0, 7}};
    // The angle r = atan2(s2, s1) is classified without trigonometry (r < 0, r > rmax = atan(d2 / d1), or
    // inside the facet); atan2 is evaluated for the chosen facet only.
    double best = 0.0, best_s1 = 0.0, best_s2 = 0.0;
    int bf = -1, best_case = 0;  // 0: r = 0 (cardinal), 1: r = rmax (diagonal), 2: inside
    for (int f = 0; f < 8; ++f) {
      const int k1 = kFacets[f][0], k2 = kFacets[f][1];
      if (!kInterior && (!g.inside(i + kDi[k1], j + kDj[k1]) || !g.inside(i + kDi[k2], j + kDj[k2]))) continue;
      const double d1 = (k1 & 2) ? g.dy : g.dx;
      const double d2 = (k1 & 2) ? g.dx : g.dy;
      const double e1 = z[c + t.off[k1]], e2 = z[c + t.off[k2]];
      const double s1 = (zc - e1) / d1, s2 = (e1 - e2) / d2;
      double s;
      int kind;
      if (s2 < 0.0) {
        s = s1, kind = 0;
      } else if (s1 <= 0.0 || s2 * d1 > s1 * d2) {
        s = (zc - e2) * t.inv_dist[k2], kind = 1;
      } else {
        s = std::sqrt(s1 * s1 + s2 * s2), kind = 2;
      }
      if (s > best) {
        best = s, bf = f, best_case = kind, best_s1 = s1, best_s2 = s2;
      }
    }
    double best_r = 0.0, best_rmax = 1.0;
    if (bf >= 0) {
      const int k1 = kFacets[bf][0];
      const double d1 = (k1 & 2) ? g.dy : g.dx, d2 = (k1 & 2) ? g.dx : g.dy;
      best_rmax = std::atan2(d2, d1);
      best_r = best_case == 0 ? 0.0 : (best_case == 1 ? best_rmax : std::min(std::atan2(best_s2, best_s1), best_rmax));
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
                      const ExecContext* ctx, std::span<float> spill_level) {
  if (g.size() == 0) return;
  if (mode == FlatMode::Flat) {
    fill_impl<false>(g, z, outlets, ctx);
    if (!spill_level.empty()) std::copy(z.begin(), z.end(), spill_level.begin());
    return;
  }
  // The flat levels exactly (a pass of their own: the epsilon flood's order is not theirs). The epsilon surface
  // of the filled heights is the epsilon surface of the heights (the header), so it starts from either.
  if (!spill_level.empty()) {
    std::copy(z.begin(), z.end(), spill_level.begin());
    fill_impl<false>(g, spill_level, outlets, ctx);
  }
  fill_impl<true>(g, z, outlets, ctx);
}

void relax_epsilon(int nx, int ny, std::span<const float> level, std::span<float> e,
                   std::span<const std::int32_t> seeds) {
  // Unraised cells (at their level) go to the monotone heap, raised ones (one ulp above the cell expanded) to
  // a FIFO that stays sorted because expanded values never decrease; the smaller front goes first. A cell
  // lowered again leaves a stale entry behind, skipped when its value no longer matches.
  MinHeap heap;
  for (const std::int32_t c : seeds) heap.push(e[static_cast<std::size_t>(c)], c);
  std::int32_t offsets[8];
  for (int k = 0; k < 8; ++k) offsets[k] = kDj[k] * nx + kDi[k];
  std::vector<QueuedCell> fifo;
  std::size_t head = 0;
  while (head < fifo.size() || !heap.empty()) {
    QueuedCell q;
    if (head < fifo.size() && (heap.empty() || fifo[head].z <= heap.peek_z())) {
      q = fifo[head];
      if (++head == fifo.size()) fifo.clear(), head = 0;
    } else {
      const Entry top = heap.pop();
      q = {top.c, top.z};
    }
    if (q.z != e[static_cast<std::size_t>(q.c)]) continue;
    const float r = next_up(q.z);
    const auto lower = [&](std::int32_t n) {
      const float v = std::max(level[static_cast<std::size_t>(n)], r);
      if (!(v < e[static_cast<std::size_t>(n)])) return;
      e[static_cast<std::size_t>(n)] = v;
      if (v == r)
        fifo.push_back({n, v});
      else
        heap.push(v, n);
    };
    const int i = q.c % nx, j = q.c / nx;
    if (i > 0 && j > 0 && i < nx - 1 && j < ny - 1) {  // an interior cell: its neighbours without bounds checks
      for (const std::int32_t o : offsets) lower(q.c + o);
      continue;
    }
    for (int k = 0; k < 8; ++k) {
      const int x = i + kDi[k], y = j + kDj[k];
      if (x >= 0 && y >= 0 && x < nx && y < ny) lower(y * nx + x);
    }
  }
}

std::vector<std::uint8_t> breach_pits(const FlowGrid& g, std::span<const float> z, const Outlets& outlets) {
  std::vector<std::uint8_t> pit(g.size(), 0);
  for (int j = 0; j < g.ny; ++j)
    for (int i = 0; i < g.nx; ++i) {
      if (outlets.is_outlet(g, i, j)) continue;
      const std::int32_t c = g.index(i, j);
      bool lower = false;
      for (int k = 0; k < 8 && !lower; ++k)
        if (g.inside(i + kDi[k], j + kDj[k])) lower = z[static_cast<std::size_t>(c + g.offset(k))] < z[c];
      pit[static_cast<std::size_t>(c)] = !lower;
    }
  return pit;
}

void breach_depressions(const FlowGrid& g, std::span<float> z, FlatMode mode, const Outlets& outlets,
                        const ExecContext* ctx) {
  if (g.size() == 0) return;
  // The tree (nodes/hydrology/breach_rule.h): the D8 receivers of the epsilon surface.
  std::vector<float> e(z.begin(), z.end());
  fill_depressions(g, e, FlatMode::Epsilon, outlets, ctx);
  const D8Flow f = d8_flow(g, e, outlets, ctx);
  e = {};
  check(ctx);
  const std::vector<std::uint8_t> pit = breach_pits(g, z, outlets);
  const std::vector<std::int32_t> order = stack_order(g, f);  // every cell after its receiver
  std::vector<float> arrived(g.size(), std::numeric_limits<float>::infinity());
  const bool epsilon = mode == FlatMode::Epsilon;
  for (auto it = order.rbegin(); it != order.rend(); ++it) {  // donors first
    const std::int32_t c = *it, r = f.receiver[static_cast<std::size_t>(c)];
    if (r == c) continue;
    const float passed = breach_passed(z[c], arrived[c], pit[c] != 0, epsilon);
    if (passed < arrived[r]) arrived[r] = passed;
  }
  for (std::size_t c = 0; c < z.size(); ++c) z[c] = std::min(z[c], arrived[c]);
}

D8Flow d8_flow(const FlowGrid& g, std::span<const float> z, const Outlets& outlets, const ExecContext* ctx) {
  D8Flow f;
  const std::size_t n = g.size();
  f.receiver.resize(n);
  f.direction.resize(n);
  f.donors.resize(n);
  const NeighbourTable t(g);
  const float* zz = z.data();
  const bool any_mask = !outlets.mask.empty();
  // One row at a time: the interior cells branch-free, neighbour by neighbour over the whole row (the same
  // slopes, comparisons and tie rule as steepest(), so the same receivers), the border cells one by one.
  auto border_cell = [&](int i, int j) {
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
  };
  for_each_row(
      ctx, g.ny,
      [&](int j) {
        if (j == 0 || j == g.ny - 1 || g.nx < 3) {
          for (int i = 0; i < g.nx; ++i) border_cell(i, j);
          return;
        }
        const int m = g.nx - 2;
        const std::int32_t c1 = g.index(1, j);
        const float* zr = zz + c1;
        std::uint8_t* dir = f.direction.data() + c1;
        std::int32_t* rec = f.receiver.data() + c1;
        // SSE2, two cells per step, all 8 neighbours in registers: the same double arithmetic as steepest()
        // (exact float -> double, subtract, multiply) and strict > in increasing k, so the same receivers.
        __m128d wv[8];
        for (int k = 0; k < 8; ++k) wv[k] = _mm_set1_pd(t.inv_dist[k]);
        const int m2 = m & ~1;
        for (int i = 0; i < m2; i += 2) {
          const __m128d a = _mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(zr + i))));
          __m128d bv = _mm_setzero_pd();
          __m128i dv = _mm_set1_epi64x(kNoDirection);
          for (int k = 0; k < 8; ++k) {
            const __m128d n =
                _mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(zr + i + t.off[k]))));
            const __m128d sv = _mm_mul_pd(_mm_sub_pd(a, n), wv[k]);
            const __m128d gt = _mm_cmpgt_pd(sv, bv);
            bv = _mm_or_pd(_mm_and_pd(gt, sv), _mm_andnot_pd(gt, bv));
            const __m128i gi = _mm_castpd_si128(gt);
            dv = _mm_or_si128(_mm_and_si128(gi, _mm_set1_epi64x(k)), _mm_andnot_si128(gi, dv));
          }
          const int k0 = _mm_cvtsi128_si32(dv), k1 = _mm_cvtsi128_si32(_mm_unpackhi_epi64(dv, dv));
          dir[i] = static_cast<std::uint8_t>(k0);
          dir[i + 1] = static_cast<std::uint8_t>(k1);
          rec[i] = c1 + i + (k0 == kNoDirection ? 0 : t.off[k0 & 7]);
          rec[i + 1] = c1 + i + 1 + (k1 == kNoDirection ? 0 : t.off[k1 & 7]);
        }
        for (int i = m2; i < m; ++i) border_cell(i + 1, j);  // odd width: the last interior cell (scalar steepest)
        border_cell(0, j);
        border_cell(g.nx - 1, j);
        if (any_mask)
          for (int i = 1; i < g.nx - 1; ++i)
            if (outlets.mask[static_cast<std::size_t>(g.index(i, j))] != 0) {
              f.direction[static_cast<std::size_t>(g.index(i, j))] = kNoDirection;
              f.receiver[static_cast<std::size_t>(g.index(i, j))] = g.index(i, j);
            }
      },
      0.0, 0.5);
  // Donor masks, again one row at a time: neighbour k is a donor when its direction points back (opposite(k)).
  auto border_donors = [&](int i, int j) {
    const std::int32_t c = g.index(i, j);
    std::uint8_t m = 0;
    for (int k = 0; k < 8; ++k)
      if (g.inside(i + kDi[k], j + kDj[k]) && f.direction[c + t.off[k]] == opposite(k))
        m |= static_cast<std::uint8_t>(1u << k);
    f.donors[c] = m;
  };
  for_each_row(
      ctx, g.ny,
      [&](int j) {
        if (j == 0 || j == g.ny - 1 || g.nx < 3) {
          for (int i = 0; i < g.nx; ++i) border_donors(i, j);
          return;
        }
        const int m = g.nx - 2;
        const std::int32_t c1 = g.index(1, j);
        std::uint8_t* dm = f.donors.data() + c1;
        const std::uint8_t* dir = f.direction.data() + c1;
        std::fill_n(dm, m, std::uint8_t{0});
        for (int k = 0; k < 8; ++k) {
          const std::uint8_t* dn = dir + t.off[k];
          const std::uint8_t want = static_cast<std::uint8_t>(opposite(k));
          const std::uint8_t bit = static_cast<std::uint8_t>(1u << k);
          for (int i = 0; i < m; ++i) dm[i] |= dn[i] == want ? bit : std::uint8_t{0};
        }
        border_donors(0, j);
        border_donors(g.nx - 1, j);
      },
      0.5, 1.0);
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

namespace {

// accumulate_d8 with `area` as the weight of every cell when `weight` is empty.
std::vector<double> accumulate_d8_of(const FlowGrid& g, const D8Flow& f, std::span<const float> weight, double area,
                                     const ExecContext* ctx) {
  const std::size_t n = f.receiver.size();
  std::vector<double> acc(n);
  std::vector<std::uint8_t> remaining(n);
  // Donor counts through a table: without -mpopcnt std::popcount is a libgcc call per cell.
  static constexpr auto kBits = [] {
    std::array<std::uint8_t, 256> b{};
    for (int v = 0; v < 256; ++v) b[v] = static_cast<std::uint8_t>(std::popcount(static_cast<unsigned>(v)));
    return b;
  }();
  auto count_donors = [&](std::size_t lo, std::size_t hi) {
    for (std::size_t c = lo; c < hi; ++c) remaining[c] = kBits[f.donors[c]];
  };
  if (tbb::this_task_arena::max_concurrency() > 1 && n >= (1u << 16))
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1u << 16),
                      [&](const tbb::blocked_range<std::size_t>& r) { count_donors(r.begin(), r.end()); });
  else
    count_donors(0, n);
  std::int32_t off[8];
  for (int k = 0; k < 8; ++k) off[k] = g.offset(k);
  const std::int32_t* rec = f.receiver.data();
  const std::uint8_t* donors = f.donors.data();
  double* a = acc.data();
  // acc of a cell whose donors are all done: its own weight plus the donors in neighbour order, so the sum
  // does not depend on which thread finished last.
  const int threads = tbb::this_task_arena::max_concurrency();
  const bool parallel = threads > 1 && n >= (1u << 16);
  const float* wts = weight.empty() ? nullptr : weight.data();
  // Parallel (after Barnes 2017): the grid is cut into bands of rows, 2 per thread. Phase 1, bands in
  // parallel with plain counters: walks stay inside their own band and a cell whose receiver lies in another
  // band is recorded instead. Phase 2, serial: the recorded cells continue their walks across bands (only
  // the cells downstream of a band boundary are left). Serial: one band, phase 1 only. Every cell is
  // computed once by the same pull (own weight plus its donors in neighbour order), so the result does not
  // depend on the band layout or the thread count.
  const int rows_per_band = parallel ? std::max(32, (g.ny + 2 * threads - 1) / (2 * threads)) : g.ny;
  const int bands = (g.ny + rows_per_band - 1) / rows_per_band;
  std::vector<std::vector<std::int32_t>> exports(static_cast<std::size_t>(bands));
  // Local restrict pointers: the byte counters would otherwise alias every pointer the loop reloads.
  auto walk = [&](std::int32_t x, std::int32_t lo, std::int32_t hi, std::vector<std::int32_t>* out) {
    const std::uint8_t* __restrict dn = donors;
    std::uint8_t* __restrict rem = remaining.data();
    const std::int32_t* __restrict rc = rec;
    double* __restrict av = a;
    const float* __restrict wv = wts;
    for (;;) {
      const std::int32_t r = rc[x];
      if (r == x) return;
      if (r < lo || r >= hi) {
        out->push_back(x);
        return;
      }
      if (--rem[r] != 0) return;
      // Pull: own weight plus the donors in neighbour order.
      double sum = wv ? static_cast<double>(wv[r]) : area;
      for (unsigned m = dn[r]; m; m &= m - 1) sum += av[r + off[std::countr_zero(m)]];
      av[r] = sum;
      x = r;
    }
  };
  auto run_band = [&](int band) {
    const std::int32_t begin = g.index(0, band * rows_per_band);
    const std::int32_t end = g.index(0, std::min(g.ny, (band + 1) * rows_per_band));
    std::vector<std::int32_t>* out = &exports[static_cast<std::size_t>(band)];
    const std::uint8_t* __restrict dn = donors;
    for (std::int32_t c0 = begin; c0 < end; c0 += 1 << 16) {
      check(ctx);
      const std::int32_t c1 = std::min(end, c0 + (1 << 16));
      auto source = [&](std::int32_t c) {
        a[c] = wts ? static_cast<double>(wts[c]) : area;
        walk(c, begin, end, out);
      };
      // Sources (no donors) found 16 at a time (SSE2 compare + bit mask) instead of one unpredictable
      // branch per cell.
      std::int32_t c = c0;
      for (; c + 16 <= c1; c += 16) {
        const __m128i v = _mm_loadu_si128(reinterpret_cast<const __m128i*>(dn + c));
        for (unsigned m = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(v, _mm_setzero_si128()))); m;
             m &= m - 1)
          source(c + std::countr_zero(m));
      }
      for (; c < c1; ++c)
        if (dn[c] == 0) source(c);
    }
  };
  if (parallel) {
    std::atomic<int> done{0};
    tbb::parallel_for(tbb::blocked_range<int>(0, bands, 1), [&](const tbb::blocked_range<int>& r) {
      for (int b = r.begin(); b != r.end(); ++b) run_band(b);
      const int d = done.fetch_add(static_cast<int>(r.size())) + static_cast<int>(r.size());
      if (ctx) ctx->progress(0.9 * d / bands);
    });
    const std::int32_t all = static_cast<std::int32_t>(n);
    for (const auto& e : exports)
      for (std::int32_t x : e) walk(x, 0, all, nullptr);
  } else {
    run_band(0);
  }
  check(ctx);
  return acc;
}

}  // namespace

std::vector<double> accumulate_d8(const FlowGrid& g, const D8Flow& f, std::span<const float> weight,
                                  const ExecContext* ctx) {
  return accumulate_d8_of(g, f, weight, g.cell_area(), ctx);
}

std::vector<double> count_d8(const FlowGrid& g, const D8Flow& f, const ExecContext* ctx) {
  return accumulate_d8_of(g, f, {}, 1.0, ctx);
}

std::vector<double> d8_area(const FlowGrid& g, const D8Flow& f, const ExecContext* ctx) {
  std::vector<double> area = count_d8(g, f, ctx);
  for (double& a : area) a *= g.cell_area();
  return area;
}

// MFD's receivers of (i, j) as route_cell finds them (bit k: neighbour k), without their weights' exp and log and
// without a branch a neighbour (which way the slope goes is a coin toss on rough ground).
template <bool kInterior>
std::uint8_t mfd_receivers(const FlowGrid& g, const NeighbourTable& t, const float* z, int i, int j,
                           const RoutingOptions& opt) {
  const std::int32_t c = g.index(i, j);
  if (routed_outlet<kInterior>(g, opt, c, i, j)) return 0;
  const double zc = z[c];
  unsigned bits = 0;
  for (int k = 0; k < 8; ++k) {
    if (!kInterior && !g.inside(i + kDi[k], j + kDj[k])) continue;
    bits |= static_cast<unsigned>(!(mfd_slope(t, z, c, zc, k) <= 0.0)) << k;
  }
  return static_cast<std::uint8_t>(bits);
}

int flow_proportions(const FlowGrid& g, std::span<const float> z, int i, int j, const RoutingOptions& opt, int nbr[8],
                     double frac[8]) {
  const NeighbourTable t(g);
  return route_cell<false>(g, t, z.data(), i, j, opt, nbr, frac);
}

FlowShares::FlowShares(const FlowGrid& g, std::span<const float> z, const RoutingOptions& opt, const ExecContext* ctx)
    : method_(opt.method) {
  const NeighbourTable t(g);
  for (int k = 0; k < 8; ++k) off_[k] = t.off[k];
  const std::size_t n = g.size();
  receivers_.assign(n, 0);
  if (opt.method == FlowMethod::D8) {
    const D8Flow f = d8_flow(g, z, opt.outlets, ctx);
    for (std::size_t c = 0; c < n; ++c)
      if (f.direction[c] != kNoDirection) receivers_[c] = static_cast<std::uint8_t>(1u << f.direction[c]);
    return;
  }
  const bool mfd = opt.method == FlowMethod::MFD;
  if (mfd) {
    // The receivers first (comparisons only), so every cell's weights have their place in one array before they
    // are computed: no row's weights are held twice.
    for_each_row(
        ctx, g.ny,
        [&](int j) {
          for (int i = 0; i < g.nx; ++i)
            receivers_[static_cast<std::size_t>(g.index(i, j))] = interior_cell(g, i, j)
                                                                      ? mfd_receivers<true>(g, t, z.data(), i, j, opt)
                                                                      : mfd_receivers<false>(g, t, z.data(), i, j, opt);
        },
        0.0, 0.1);
    block_first_.resize((n + kBlock - 1) / kBlock);
    before_in_block_.resize(n);
    std::uint64_t weights = 0;
    for (std::size_t c = 0; c < n; ++c) {
      if (c % kBlock == 0) block_first_[c / kBlock] = weights;
      before_in_block_[c] = static_cast<std::uint8_t>(weights - block_first_[c / kBlock]);
      weights += static_cast<std::uint64_t>(bit_count(receivers_[c]));
    }
    weights_.resize(weights + 8);
  } else {
    split_.assign(n, 1.0f);
  }
  for_each_row(
      ctx, g.ny,
      [&](int j) {
        for (int i = 0; i < g.nx; ++i) {
          int nb[8];
          double fr[8];
          const auto c = static_cast<std::size_t>(g.index(i, j));
          // MFD's weights go straight to their place (a copy of a few floats was a slow `rep movs`); weights_ has
          // 8 floats of slack at its end, so a count that disagreed with the receivers' (refused below) stays inside.
          float* to = mfd ? weights_.data() + block_first_[c / kBlock] + before_in_block_[c] : nullptr;
          const int cnt = interior_cell(g, i, j) ? route_cell<true>(g, t, z.data(), i, j, opt, nb, fr, to)
                                                 : route_cell<false>(g, t, z.data(), i, j, opt, nb, fr, to);
          if (mfd) {
            if (cnt != bit_count(receivers_[c]))
              throw std::logic_error("flow shares: MFD receivers changed between their two passes");
          } else {
            std::uint8_t bits = 0;
            for (int m = 0; m < cnt; ++m) bits |= static_cast<std::uint8_t>(1u << nb[m]);
            receivers_[c] = bits;
            if (cnt == 2) split_[c] = static_cast<float>(fr[0]);  // nb[0] is the facet's cardinal neighbour
          }
        }
      },
      mfd ? 0.1 : 0.0, 0.3);
}

std::vector<double> accumulate(const FlowGrid& g, std::span<const float> z, const RoutingOptions& opt,
                               std::span<const float> weight, const ExecContext* ctx) {
  if (opt.method == FlowMethod::D8) return accumulate_d8(g, d8_flow(g, z, opt.outlets, ctx), weight, ctx);
  const std::size_t n = g.size();
  const FlowShares shares(g, z, opt, ctx);
  const NeighbourTable t(g);
  // Number of neighbours that send flow to each cell.
  std::vector<std::uint8_t> remaining(n);
  for_each_row(
      ctx, g.ny,
      [&](int j) {
        for (int i = 0; i < g.nx; ++i) {
          const std::int32_t c = g.index(i, j);
          int cnt = 0;
          const bool interior = interior_cell(g, i, j);
          for (int k = 0; k < 8; ++k)
            if (interior || g.inside(i + kDi[k], j + kDj[k])) cnt += shares.donor(c, k);
          remaining[static_cast<std::size_t>(c)] = static_cast<std::uint8_t>(cnt);
        }
      },
      0.3, 0.5);
  std::vector<double> acc(n);
  const double area = g.cell_area();
  // A cell whose donors are all done: its own weight plus their shares pulled in neighbour order (flow_shares.h),
  // so its value does not depend on the order in which the traversal below reaches it.
  auto pull = [&](std::int32_t c) __attribute__((always_inline)) {
    double sum = cell_weight(weight, static_cast<std::size_t>(c), area);
    const int i = g.column(c), j = g.row(c);
    const bool interior = interior_cell(g, i, j);
    for (int k = 0; k < 8; ++k) {
      if (!interior && !g.inside(i + kDi[k], j + kDj[k])) continue;
      if (!shares.donor(c, k)) continue;
      const std::int32_t m = c + t.off[k];
      sum += acc[static_cast<std::size_t>(m)] * shares.fraction(m, opposite(k));
    }
    acc[static_cast<std::size_t>(c)] = sum;
  };
  // Parallel after Barnes 2017: the rows are cut into a fixed number of bands, merged pairwise up a binary tree. A
  // leaf does dependency counting inside its band; a receiver outside the band is recorded instead of counted down.
  // A tree node counts down the cells its two halves recorded inside its range and continues downstream from those
  // they complete, again recording what leaves its range; the halves run in parallel. Every cell is pulled once,
  // when its donors are done, so the result is the same for any thread count and band layout. Only the root's work
  // is serial (about a tenth of the cells on 4096^2 fBm with MFD).
  constexpr std::uint8_t kDone = 0xFF;
  const int rows_per_band = std::max(64, (g.ny + 7) / 8);
  const int bands = (g.ny + rows_per_band - 1) / rows_per_band;
  const bool parallel = tbb::this_task_arena::max_concurrency() > 1 && bands > 1;
  // Counts down x's receivers; those in [lo, hi) that complete are pulled and pushed on `st`, the others recorded
  // in `out`.
  auto route = [&](std::int32_t x, std::int32_t lo, std::int32_t hi, std::vector<std::int32_t> & st,
                   std::vector<std::int32_t> & out) __attribute__((always_inline)) {
    const std::uint32_t span = static_cast<std::uint32_t>(hi - lo);
    for (unsigned b = shares.receivers(x); b; b &= b - 1) {
      const std::int32_t m = x + t.off[std::countr_zero(b)];
      if (static_cast<std::uint32_t>(m - lo) >= span) {
        out.push_back(m);
        continue;
      }
      if (--remaining[static_cast<std::size_t>(m)] == 0) {
        remaining[static_cast<std::size_t>(m)] = kDone;
        pull(m);
        st.push_back(m);
      }
    }
  };
  auto drain = [&](std::int32_t lo, std::int32_t hi, std::vector<std::int32_t>& st, std::vector<std::int32_t>& out) {
    while (!st.empty()) {
      const std::int32_t x = st.back();
      st.pop_back();
      route(x, lo, hi, st, out);
    }
  };
  auto band_begin = [&](int b) { return g.index(0, std::min(g.ny, b * rows_per_band)); };
  std::atomic<int> leaves_done{0};
  std::function<std::vector<std::int32_t>(int, int)> solve = [&](int b0, int b1) -> std::vector<std::int32_t> {
    const std::int32_t lo = band_begin(b0), hi = band_begin(b1);
    std::vector<std::int32_t> out, st;
    std::size_t work = 0;
    if (b1 - b0 == 1) {
      for (std::int32_t c0 = lo; c0 < hi; ++c0) {
        if (remaining[static_cast<std::size_t>(c0)] != 0) continue;
        remaining[static_cast<std::size_t>(c0)] = kDone;
        pull(c0);
        st.push_back(c0);
        drain(lo, hi, st, out);
        if (++work > (1u << 16)) {
          work = 0;
          check(ctx);
        }
      }
      const int d = leaves_done.fetch_add(1) + 1;
      if (ctx) ctx->progress(0.5 + 0.4 * d / bands);
      return out;
    }
    const int mid = (b0 + b1) / 2;
    std::vector<std::int32_t> left, right;
    if (parallel)
      tbb::parallel_invoke([&] { left = solve(b0, mid); }, [&] { right = solve(mid, b1); });
    else
      left = solve(b0, mid), right = solve(mid, b1);
    for (const std::vector<std::int32_t>* in : {&left, &right})
      for (const std::int32_t m : *in) {
        if (m < lo || m >= hi) {
          out.push_back(m);
          continue;
        }
        if (--remaining[static_cast<std::size_t>(m)] != 0) continue;
        remaining[static_cast<std::size_t>(m)] = kDone;
        pull(m);
        st.push_back(m);
        drain(lo, hi, st, out);
        if (++work > (1u << 14)) {
          work = 0;
          check(ctx);
        }
      }
    return out;
  };
  solve(0, bands);
  check(ctx);
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
