#include "nodes/hydrology/basin_graph.h"

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "graph/exec_context.h"

namespace orogen::hydrology {
namespace {

void check(const ExecContext* ctx) {
  if (ctx) ctx->check_cancelled();
}

// Rows per stack chunk: the outlets of a chunk of rows and their trees form one contiguous piece of the stack.
// A fixed size (not one per thread), so the pieces and their order do not depend on the thread count.
constexpr int kChunkRows = 16;

struct Edge {
  double w;           // pass height max(z_x, z_y)
  std::int32_t a, b;  // basin nodes (0: the outlets), a < b
  std::int32_t x, y;  // the cells on either side: x in basin b... (see orient)
  bool operator<(const Edge& o) const {
    if (w != o.w) return w < o.w;
    if (a != o.a) return a < o.a;
    if (b != o.b) return b < o.b;
    if (x != o.x) return x < o.x;
    return y < o.y;
  }
};

// Direction k from cell c to its 8-neighbour r.
inline int direction_to(const FlowGrid& g, std::int32_t c, std::int32_t r) {
  const int di = g.column(r) - g.column(c), dj = g.row(r) - g.row(c);
  for (int k = 0; k < 8; ++k)
    if (kDi[k] == di && kDj[k] == dj) return k;
  return kNoDirection;
}

template <class T>
void d8_pass(const FlowGrid& g, const T* z, const Outlets& outlets, BasinRouting& r, std::vector<int>& row_outlets,
             const ExecContext* ctx) {
  const std::size_t n = g.size();
  D8Flow& f = r.flow;
  f.receiver.resize(n);
  f.direction.resize(n);
  f.donors.resize(n);
  r.row_pits_.assign(static_cast<std::size_t>(g.ny), 0);
  row_outlets.assign(static_cast<std::size_t>(g.ny), 0);
  std::int32_t off[8];
  double inv[8];
  for (int k = 0; k < 8; ++k) {
    off[k] = g.offset(k);
    inv[k] = 1.0 / g.distance(k);
  }
  const bool any_mask = !outlets.mask.empty();
  tbb::parallel_for(tbb::blocked_range<int>(0, g.ny, 8), [&](const tbb::blocked_range<int>& rows) {
    check(ctx);
    std::vector<double> best_row(static_cast<std::size_t>(g.nx));
    std::vector<int> k_row(static_cast<std::size_t>(g.nx));
    for (int j = rows.begin(); j != rows.end(); ++j) {
      int pits = 0, outs = 0;
      const bool edge_row = j == 0 || j == g.ny - 1;
      const std::int32_t c0 = g.index(0, j);
      // Interior cells neighbour by neighbour over the whole row (branch-free, vectorisable); the same
      // slopes and strict > in increasing k as the scalar rule below, so the same receivers.
      if (!edge_row && g.nx > 2) {
        double* best = best_row.data();
        int* bk = k_row.data();
        const T* zc = z + c0;
        for (int i = 1; i < g.nx - 1; ++i) best[i] = 0.0, bk[i] = kNoDirection;
        for (int k = 0; k < 8; ++k) {
          const T* zn = zc + off[k];
          const double w = inv[k];
          for (int i = 1; i < g.nx - 1; ++i) {
            const double sl = (static_cast<double>(zc[i]) - static_cast<double>(zn[i])) * w;
            const bool gt = sl > best[i];
            best[i] = gt ? sl : best[i];
            bk[i] = gt ? k : bk[i];
          }
        }
      }
      for (int i = 0; i < g.nx; ++i) {
        const std::int32_t c = c0 + i;
        const bool outlet = (outlets.border && (edge_row || i == 0 || i == g.nx - 1)) ||
                            (any_mask && outlets.mask[static_cast<std::size_t>(c)] != 0);
        int best_k = kNoDirection;
        if (!outlet) {
          if (!edge_row && i > 0 && i < g.nx - 1) {
            best_k = k_row[static_cast<std::size_t>(i)];
          } else {
            const double zc = static_cast<double>(z[c]);
            double best = 0.0;
            for (int k = 0; k < 8; ++k) {
              if (!g.inside(i + kDi[k], j + kDj[k])) continue;
              const double sl = (zc - static_cast<double>(z[c + off[k]])) * inv[k];
              if (sl > best) best = sl, best_k = k;
            }
          }
          pits += best_k == kNoDirection;
        } else {
          ++outs;
        }
        f.direction[c] = static_cast<std::uint8_t>(best_k);
        f.receiver[c] = best_k == kNoDirection ? c : c + off[best_k];
      }
      r.row_pits_[static_cast<std::size_t>(j)] = pits;
      row_outlets[static_cast<std::size_t>(j)] = outs;
    }
  });
  tbb::parallel_for(tbb::blocked_range<int>(0, g.ny, 8), [&](const tbb::blocked_range<int>& rows) {
    for (int j = rows.begin(); j != rows.end(); ++j) {
      const bool edge_row = j == 0 || j == g.ny - 1;
      for (int i = 0; i < g.nx; ++i) {
        const std::int32_t c = g.index(i, j);
        std::uint8_t m = 0;
        if (!edge_row && i > 0 && i < g.nx - 1) {
          for (int k = 0; k < 8; ++k)
            m |= f.direction[c + off[k]] == opposite(k) ? static_cast<std::uint8_t>(1u << k) : std::uint8_t{0};
        } else {
          for (int k = 0; k < 8; ++k)
            if (g.inside(i + kDi[k], j + kDj[k]) && f.direction[c + off[k]] == opposite(k))
              m |= static_cast<std::uint8_t>(1u << k);
        }
        f.donors[c] = m;
      }
    }
  });
}

// Reroutes the pits through the minimum spanning tree of the basin graph (steps 3-5 of the header).
// Just above v: the gradient a filled lake keeps towards its pass.
inline double raise_above(double v) { return v + std::max(1e-9, std::abs(v) * 1e-12); }
inline float raise_above(float v) { return std::nextafter(v, std::numeric_limits<float>::infinity()); }

// D8 receiver direction of interior or border cell c (the rule of d8_pass).
template <class T>
int steepest_k(const FlowGrid& g, const T* z, std::int32_t c, const std::int32_t* off, const double* inv) {
  const int i = g.column(c), j = g.row(c);
  const double zc = static_cast<double>(z[c]);
  double best = 0.0;
  int best_k = kNoDirection;
  for (int k = 0; k < 8; ++k) {
    if (!g.inside(i + kDi[k], j + kDj[k])) continue;
    const double s = (zc - static_cast<double>(z[c + off[k]])) * inv[k];
    if (s > best) best = s, best_k = k;
  }
  return best_k;
}

// fill == nullptr: carve only. Otherwise fill points at the heights (the same array as z) and the lakes are
// raised, then their cells re-routed by D8 over the filled surface; `raised` collects the raise.
template <class T>
void reroute_pits(const FlowGrid& g, const T* z, const Outlets& outlets, BasinRouting& r, bool have_outlets,
                  T* fill = nullptr, std::span<double> raised = {}) {
  D8Flow& f = r.flow;
  const std::size_t n = g.size();
  std::int32_t off[8];
  double inv[8];
  for (int k = 0; k < 8; ++k) off[k] = g.offset(k), inv[k] = 1.0 / g.distance(k);
  const bool any_mask = !outlets.mask.empty();
  std::vector<std::int32_t> pits;
  for (int j = 0; j < g.ny; ++j) {
    if (r.row_pits_[static_cast<std::size_t>(j)] == 0) continue;
    for (int i = 0; i < g.nx; ++i) {
      const std::int32_t c = g.index(i, j);
      if (f.receiver[c] != c) continue;
      const bool outlet =
          (outlets.border && g.on_border(i, j)) || (any_mask && outlets.mask[static_cast<std::size_t>(c)] != 0);
      if (!outlet) pits.push_back(c);
    }
  }
  r.pits = 0;
  r.pit_cells = 0;
  r.graph_edges = 0;
  r.tree_edges = 0;
  if (pits.empty()) return;
  if (!have_outlets) {
    // The basin of the lowest pit plays the outlets' part (node 0, never rerouted).
    auto lowest = std::min_element(pits.begin(), pits.end(), [&](std::int32_t a, std::int32_t b) {
      return z[a] < z[b] || (z[a] == z[b] && a < b);
    });
    pits.erase(lowest);
    if (pits.empty()) return;
  }
  const std::int32_t P = static_cast<std::int32_t>(pits.size());
  r.label_.resize(n, 0);  // zero everywhere between calls
  std::int32_t* label = r.label_.data();
  // Basins: the pit's upstream cells, by a walk over the donors; one pit per task (disjoint cells).
  std::vector<std::vector<std::int32_t>> basin(static_cast<std::size_t>(P));
  tbb::parallel_for(tbb::blocked_range<std::int32_t>(1, P + 1, 1), [&](const tbb::blocked_range<std::int32_t>& br) {
    std::vector<std::int32_t> st;
    for (std::int32_t b = br.begin(); b != br.end(); ++b) {
      auto& out = basin[static_cast<std::size_t>(b) - 1];
      st.push_back(pits[static_cast<std::size_t>(b) - 1]);
      while (!st.empty()) {
        const std::int32_t x = st.back();
        st.pop_back();
        label[x] = b;
        out.push_back(x);
        for (unsigned m = f.donors[x]; m; m &= m - 1) st.push_back(x + off[std::countr_zero(m)]);
      }
    }
  });
  // Basin graph: the lowest pass between each pit basin and each neighbouring basin (the outlets count as one
  // node, 0). Each pair of pit basins is seen from the lower-numbered one only. One basin per task, its edges
  // in its own list; the lists are then joined in basin order.
  std::vector<std::vector<Edge>> basin_edges(static_cast<std::size_t>(P));
  std::vector<std::size_t> basin_candidates(static_cast<std::size_t>(P));
  tbb::parallel_for(tbb::blocked_range<std::int32_t>(1, P + 1, 1), [&](const tbb::blocked_range<std::int32_t>& br) {
    std::vector<std::int32_t> slot(static_cast<std::size_t>(P) + 1, -1), touched;
    for (std::int32_t b = br.begin(); b != br.end(); ++b) {
      auto& edges = basin_edges[static_cast<std::size_t>(b) - 1];
      std::size_t candidates = 0;
      for (const std::int32_t x : basin[static_cast<std::size_t>(b) - 1]) {
        const int i = g.column(x), j = g.row(x);
        const bool interior = i > 0 && j > 0 && i < g.nx - 1 && j < g.ny - 1;
        const double zx = static_cast<double>(z[x]);
        for (int k = 0; k < 8; ++k) {
          if (!interior && !g.inside(i + kDi[k], j + kDj[k])) continue;
          const std::int32_t y = x + off[k];
          const std::int32_t lb = label[y];
          if (lb == b || (lb != 0 && lb < b)) continue;
          ++candidates;
          const Edge e{std::max(zx, static_cast<double>(z[y])), lb, b, x, y};
          std::int32_t& sl = slot[static_cast<std::size_t>(lb)];
          if (sl < 0) {
            sl = static_cast<std::int32_t>(edges.size());
            edges.push_back(e);
            touched.push_back(lb);
          } else if (e < edges[static_cast<std::size_t>(sl)]) {
            edges[static_cast<std::size_t>(sl)] = e;
          }
        }
      }
      for (std::int32_t t : touched) slot[static_cast<std::size_t>(t)] = -1;
      touched.clear();
      basin_candidates[static_cast<std::size_t>(b) - 1] = candidates;
    }
  });
  std::vector<Edge> edges;
  std::size_t candidates = 0, pit_cells = 0;
  for (std::int32_t b = 0; b < P; ++b) {
    edges.insert(edges.end(), basin_edges[static_cast<std::size_t>(b)].begin(),
                 basin_edges[static_cast<std::size_t>(b)].end());
    candidates += basin_candidates[static_cast<std::size_t>(b)];
    pit_cells += basin[static_cast<std::size_t>(b)].size();
  }
  std::vector<std::int32_t> st;
  // Kruskal over the basin graph.
  std::sort(edges.begin(), edges.end());
  std::vector<std::int32_t> parent(static_cast<std::size_t>(P) + 1);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::int32_t a) {
    while (parent[static_cast<std::size_t>(a)] != a) {
      parent[static_cast<std::size_t>(a)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(a)])];
      a = parent[static_cast<std::size_t>(a)];
    }
    return a;
  };
  std::vector<std::int32_t> tree;  // indices into edges
  for (std::size_t e = 0; e < edges.size() && static_cast<std::int32_t>(tree.size()) < P; ++e) {
    const std::int32_t ra = find(edges[e].a), rb = find(edges[e].b);
    if (ra == rb) continue;
    parent[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
    tree.push_back(static_cast<std::int32_t>(e));
  }
  // Orient the tree from node 0 (breadth first) and reroute every child basin's pit to its pass.
  std::vector<std::int32_t> deg(static_cast<std::size_t>(P) + 2, 0), adj(tree.size() * 2);
  for (std::int32_t e : tree)
    ++deg[static_cast<std::size_t>(edges[e].a) + 1], ++deg[static_cast<std::size_t>(edges[e].b) + 1];
  std::partial_sum(deg.begin(), deg.end(), deg.begin());
  {
    std::vector<std::int32_t> fillp(deg.begin(), deg.end() - 1);
    for (std::int32_t e : tree) {
      adj[static_cast<std::size_t>(fillp[static_cast<std::size_t>(edges[e].a)]++)] = e;
      adj[static_cast<std::size_t>(fillp[static_cast<std::size_t>(edges[e].b)]++)] = e;
    }
  }
  r.carved_.resize(n, 0);  // zero everywhere between calls
  std::uint8_t* carved = r.carved_.data();
  std::vector<std::int32_t> carved_cells;
  auto set_receiver = [&](std::int32_t c, std::int32_t rn) {
    const std::int32_t old = f.receiver[c];
    if (old != c) f.donors[old] &= static_cast<std::uint8_t>(~(1u << opposite(f.direction[c])));
    const int k = direction_to(g, c, rn);
    f.receiver[c] = rn;
    f.direction[c] = static_cast<std::uint8_t>(k);
    f.donors[rn] |= static_cast<std::uint8_t>(1u << opposite(k));
  };
  std::vector<std::uint8_t> seen(static_cast<std::size_t>(P) + 1, 0);
  std::vector<std::int32_t> pass_of(static_cast<std::size_t>(P) + 1, -1);
  std::vector<std::int32_t> queue{0};
  seen[0] = 1;
  for (std::size_t h = 0; h < queue.size(); ++h) {
    const std::int32_t u = queue[h];
    for (std::int32_t q = deg[static_cast<std::size_t>(u)]; q < deg[static_cast<std::size_t>(u) + 1]; ++q) {
      const Edge& e = edges[static_cast<std::size_t>(adj[static_cast<std::size_t>(q)])];
      const std::int32_t v = e.a == u ? e.b : e.a;
      if (seen[static_cast<std::size_t>(v)]) continue;
      seen[static_cast<std::size_t>(v)] = 1;
      queue.push_back(v);
      pass_of[static_cast<std::size_t>(v)] = -1;
      // The pass cell on v's side and the cell across: x lies in basin e.b (the side it was scanned from).
      std::int32_t in_v = e.x, across = e.y;
      if (e.b != v) std::swap(in_v, across);
      // When the pass cell itself is the spill height, every lower neighbour across in basin u is a pass of
      // that height: leave by the steepest (as water spilling over the rim would), not the lowest index.
      if (z[in_v] >= z[across]) {
        const int i = g.column(in_v), j = g.row(in_v);
        const double zv = static_cast<double>(z[in_v]);
        double best = -1.0;
        for (int k = 0; k < 8; ++k) {
          if (!g.inside(i + kDi[k], j + kDj[k])) continue;
          const std::int32_t y = in_v + off[k];
          if (label[y] != u || z[y] > z[in_v]) continue;
          const double s = (zv - static_cast<double>(z[y])) * inv[k];
          if (s > best) best = s, across = y;
        }
      }
      // Carve: reverse the receivers from the pass cell down to the pit, then cross the pass.
      std::int32_t prev = across, cur = in_v;
      for (;;) {
        const std::int32_t next = f.receiver[cur];
        set_receiver(cur, prev);
        carved[cur] = 1;
        carved_cells.push_back(cur);
        if (next == cur) break;
        prev = cur;
        cur = next;
      }
      pass_of[static_cast<std::size_t>(v)] = in_v;
    }
  }
  if (fill) {
    // Parents before children (breadth-first order of the tree): every lake cell ends just above its carved
    // receiver, whose height is already final (its own basin, walked from the pass, or the parent basin).
    // The walk stops at cells left as they were: their donors drain into them by D8 and are higher, unless
    // the carve reversed them (carved cells are always visited).
    std::vector<std::int32_t> raised_cells;
    for (std::size_t h = 1; h < queue.size(); ++h) {
      const std::int32_t v = queue[h];
      st.push_back(pass_of[static_cast<std::size_t>(v)]);
      while (!st.empty()) {
        const std::int32_t x = st.back();
        st.pop_back();
        const T zr = fill[f.receiver[x]];
        bool up = false;
        if (fill[x] <= zr) {
          const T nz = raise_above(zr);
          if (!raised.empty())
            raised[static_cast<std::size_t>(x)] += static_cast<double>(nz) - static_cast<double>(fill[x]);
          fill[x] = nz;
          raised_cells.push_back(x);
          up = true;
        }
        for (unsigned m = f.donors[x]; m; m &= m - 1) {
          const std::int32_t y = x + off[std::countr_zero(m)];
          if (label[y] == v && (up || carved[y])) st.push_back(y);
        }
      }
    }
    // Every lake cell is now above a neighbour: steepest descent over the filled surface, as after a
    // Priority-Flood fill, for the raised cells and their neighbours in pit basins (elsewhere nothing changes:
    // only neighbours rose).
    std::vector<std::int32_t> redo;  // each cell once (bit 2 of carved marks it)
    for (const std::int32_t c : raised_cells) {
      const int i = g.column(c), j = g.row(c);
      for (int k = -1; k < 8; ++k) {
        if (k >= 0 && !g.inside(i + kDi[k], j + kDj[k])) continue;
        const std::int32_t y = k < 0 ? c : c + off[k];
        if (label[y] == 0 || (carved[y] & 2)) continue;
        carved[y] |= 2;
        redo.push_back(y);
      }
    }
    for (const std::int32_t y : redo) {
      const int d = steepest_k(g, z, y, off, inv);
      if (d != f.direction[y] && d != kNoDirection) set_receiver(y, y + off[d]);
      carved[y] &= static_cast<std::uint8_t>(~2u);
    }
  }
  for (std::int32_t c : carved_cells) carved[c] = 0;
  tbb::parallel_for(tbb::blocked_range<std::int32_t>(0, P, 1), [&](const tbb::blocked_range<std::int32_t>& br) {
    for (std::int32_t b = br.begin(); b != br.end(); ++b)
      for (std::int32_t c : basin[static_cast<std::size_t>(b)]) label[c] = 0;
  });
  r.pits = P;
  r.pit_cells = static_cast<int>(pit_cells);
  r.graph_edges = static_cast<int>(candidates);
  r.tree_edges = static_cast<int>(tree.size());
}

// Step 6: the stack, one piece per chunk of rows built in parallel, concatenated in chunk order.
void build_stack(const FlowGrid& g, BasinRouting& r) {
  const D8Flow& f = r.flow;
  const int chunks = (g.ny + kChunkRows - 1) / kChunkRows;
  auto& piece = r.pieces_;  // kept between calls: no new pages for the next step
  auto& roots = r.piece_roots_;
  piece.resize(static_cast<std::size_t>(chunks));
  roots.resize(static_cast<std::size_t>(chunks));
  for (int ch = 0; ch < chunks; ++ch)
    piece[static_cast<std::size_t>(ch)].clear(), roots[static_cast<std::size_t>(ch)].clear();
  std::int32_t off[8];
  for (int k = 0; k < 8; ++k) off[k] = g.offset(k);
  tbb::parallel_for(tbb::blocked_range<int>(0, chunks, 1), [&](const tbb::blocked_range<int>& cr) {
    std::vector<std::int32_t> st;
    for (int ch = cr.begin(); ch != cr.end(); ++ch) {
      auto& out = piece[static_cast<std::size_t>(ch)];
      auto& rt = roots[static_cast<std::size_t>(ch)];
      const std::int32_t c0 = g.index(0, ch * kChunkRows);
      const std::int32_t c1 = g.index(0, std::min(g.ny, (ch + 1) * kChunkRows));
      for (std::int32_t c = c0; c < c1; ++c) {
        if (f.receiver[c] != c) continue;
        rt.push_back(static_cast<std::int32_t>(out.size()));
        st.push_back(c);
        while (!st.empty()) {
          const std::int32_t x = st.back();
          st.pop_back();
          out.push_back(x);
          for (unsigned m = f.donors[x]; m; m &= m - 1) st.push_back(x + off[std::countr_zero(m)]);
        }
      }
    }
  });
  std::vector<std::size_t> at(static_cast<std::size_t>(chunks) + 1, 0), tat(static_cast<std::size_t>(chunks) + 1, 0);
  for (int ch = 0; ch < chunks; ++ch) {
    at[static_cast<std::size_t>(ch) + 1] =
        at[static_cast<std::size_t>(ch)] + piece[static_cast<std::size_t>(ch)].size();
    tat[static_cast<std::size_t>(ch) + 1] =
        tat[static_cast<std::size_t>(ch)] + roots[static_cast<std::size_t>(ch)].size();
  }
  r.stack.resize(at.back());
  r.tree_begin.resize(tat.back() + 1);
  r.tree_begin.back() = static_cast<std::int32_t>(at.back());
  tbb::parallel_for(tbb::blocked_range<int>(0, chunks, 1), [&](const tbb::blocked_range<int>& cr) {
    for (int ch = cr.begin(); ch != cr.end(); ++ch) {
      const auto& p = piece[static_cast<std::size_t>(ch)];
      std::copy(p.begin(), p.end(), r.stack.begin() + static_cast<std::ptrdiff_t>(at[static_cast<std::size_t>(ch)]));
      const auto& rt = roots[static_cast<std::size_t>(ch)];
      for (std::size_t q = 0; q < rt.size(); ++q)
        r.tree_begin[tat[static_cast<std::size_t>(ch)] + q] =
            static_cast<std::int32_t>(at[static_cast<std::size_t>(ch)]) + rt[q];
    }
  });
}

template <class T>
void route_impl(const FlowGrid& g, std::span<const T> z, const Outlets& outlets, BasinRouting& r,
                const ExecContext* ctx, T* fill = nullptr, std::span<double> raised = {}) {
  r.pits = r.pit_cells = r.graph_edges = r.tree_edges = 0;
  if (g.size() == 0) {
    r.flow = {};
    r.stack.clear();
    r.tree_begin.assign(1, 0);
    return;
  }
  std::vector<int> row_outlets;
  d8_pass(g, z.data(), outlets, r, row_outlets, ctx);
  const bool have_outlets = std::any_of(row_outlets.begin(), row_outlets.end(), [](int c) { return c > 0; });
  if (std::any_of(r.row_pits_.begin(), r.row_pits_.end(), [](int c) { return c > 0; })) {
    check(ctx);
    reroute_pits(g, z.data(), outlets, r, have_outlets, fill, raised);
  }
  check(ctx);
  build_stack(g, r);
}

}  // namespace

void route_basin_graph(const FlowGrid& g, std::span<const double> z, const Outlets& outlets, BasinRouting& r,
                       const ExecContext* ctx) {
  route_impl(g, z, outlets, r, ctx);
}

void route_basin_graph(const FlowGrid& g, std::span<const float> z, const Outlets& outlets, BasinRouting& r,
                       const ExecContext* ctx) {
  route_impl(g, z, outlets, r, ctx);
}

void route_basin_graph_fill(const FlowGrid& g, std::span<double> z, const Outlets& outlets, BasinRouting& r,
                            std::span<double> raised, const ExecContext* ctx) {
  route_impl(g, std::span<const double>(z), outlets, r, ctx, z.data(), raised);
}

void route_basin_graph_fill(const FlowGrid& g, std::span<float> z, const Outlets& outlets, BasinRouting& r,
                            std::span<double> raised, const ExecContext* ctx) {
  route_impl(g, std::span<const float>(z), outlets, r, ctx, z.data(), raised);
}

void accumulate_stack(const FlowGrid& g, const BasinRouting& r, std::span<double> acc, std::span<const float> weight) {
  const std::int32_t* rcv = r.flow.receiver.data();
  const double area = g.cell_area();
  for_each_tree(r, [&](std::int32_t first, std::int32_t last) {
    for (std::int32_t q = first; q < last; ++q) {
      const std::int32_t c = r.stack[static_cast<std::size_t>(q)];
      acc[c] = weight.empty() ? area : static_cast<double>(weight[c]);
    }
    for (std::int32_t q = last - 1; q > first; --q) {
      const std::int32_t c = r.stack[static_cast<std::size_t>(q)];
      acc[rcv[c]] += acc[c];
    }
  });
}

}  // namespace orogen::hydrology
