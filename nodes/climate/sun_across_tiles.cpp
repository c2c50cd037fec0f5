// SunIllumination across the tiles of a tiled or distributed build, exact (graph/tile_graph.h).
//
// The whole-domain node sweeps, for every sun direction, straight lines parallel to the sun's azimuth away from the
// sun, sampling each where it crosses a column (nodes/climate/sun_sweep.h); a line sample's horizon comes from the
// upper hull of the samples ahead of it on its line. Every line sample lies between two samples of one column, and
// belongs to the tile holding that column and that pair of samples (the tile of largest index on a shared column or
// sample), so each line passes through a chain of tiles, each further along the sweep on both axes. A tile computes
// its line samples with the same arithmetic as the whole-domain sweep (positions from whole-domain indices) once it
// holds the hull of each line entering it, and hands each line leaving it on to the next tile with its hull.
//
// Round 0: each tile sends its largest height steps (the bound above which the sun casts no shadow is the whole
// domain's) and its border bands one sample deep (its normals need its neighbors' heights); it gets the largest steps,
// the tiling and its halo. Rounds 1 .. nx + ny - 1 are a wavefront: in round r a tile sweeps every sun direction for
// which r - 1 tiles lie upstream of it (along x and y toward the sun), with the hulls it received, and sends the
// hulls of the lines leaving it, addressed to the tiles they enter. All sun directions of a round travel together,
// so the rounds do not grow with their number. Last round: a cell on a tile's last column or row in a sweep reads
// line samples of its neighbors, so each tile sends the line samples on its first column and first and last rows
// of each sweep, and gets those its border cells read. A tile then adds up its cells' lit hours and irradiance in the
// whole-domain run's order of sun positions.
#include "nodes/climate/sun_across_tiles.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <unordered_map>

#include <tbb/parallel_for.h>

#include "graph/calendar.h"
#include "graph/node_type.h"
#include "graph/registry.h"
#include "graph/sample_rect.h"
#include "graph/tile_bytes.h"
#include "graph/tile_graph.h"
#include "nodes/climate/sun_sweep.h"
#include "nodes/erosion/tile_bands.h"
#include "nodes/field/surface_derivatives.h"

namespace orogen::climate {
namespace {

constexpr const char* kWhat = "sun across tiles";

constexpr std::size_t kHullPointBytes = sizeof(std::int32_t) + sizeof(double);  // its step and height

[[noreturn]] void refuse(const std::string& why) { throw std::invalid_argument(std::string(kWhat) + ": " + why); }

// The tiling: the first sample of each tile column and row. A sample (or line sample) belongs to the tile of largest
// index whose first sample is at or before it: tiles share their border samples, the next tile takes them.
struct Grid {
  std::vector<int> xs, ys;
  int nx() const { return static_cast<int>(xs.size()); }
  int ny() const { return static_cast<int>(ys.size()); }
  static int owner(const std::vector<int>& lo, int v) {
    return static_cast<int>(std::upper_bound(lo.begin(), lo.end(), v) - lo.begin()) - 1;
  }
  glm::ivec2 index(const SampleRect& r) const { return {owner(xs, r.lo.x), owner(ys, r.lo.y)}; }
};

// The grid of the tiles `rects`, which must tile the whole domain `whole`.
Grid grid_of(const std::vector<SampleRect>& rects, glm::ivec2 whole) {
  if (rects.empty()) refuse("no tiles");
  Grid g;
  for (const SampleRect& r : rects) {
    erosion::check_tile_rect(r, whole, kWhat);
    g.xs.push_back(r.lo.x), g.ys.push_back(r.lo.y);
  }
  for (auto* v : {&g.xs, &g.ys}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  if (static_cast<std::size_t>(g.nx()) * static_cast<std::size_t>(g.ny()) != rects.size() || g.xs[0] != 0 ||
      g.ys[0] != 0)
    refuse("the tiles do not form a tiling");
  std::vector<char> seen(rects.size(), 0);
  for (const SampleRect& r : rects) {
    const glm::ivec2 t = g.index(r);
    const int hx = t.x + 1 < g.nx() ? g.xs[static_cast<std::size_t>(t.x + 1)] : whole.x - 1;
    const int hy = t.y + 1 < g.ny() ? g.ys[static_cast<std::size_t>(t.y + 1)] : whole.y - 1;
    char& s = seen[static_cast<std::size_t>(t.y) * static_cast<std::size_t>(g.nx()) + static_cast<std::size_t>(t.x)];
    if (r.hi.x != hx || r.hi.y != hy || s) refuse("the tiles do not form a tiling");
    s = 1;
  }
  return g;
}

std::vector<SampleRect> rects_of(const std::vector<std::string>& messages) {
  std::vector<SampleRect> rects;
  for (const std::string& m : messages) {
    std::string_view in(m);
    rects.push_back(bytes::take<SampleRect>(in, kWhat));
  }
  return rects;
}

// What a sun position does to the cells: nothing (night), light them all (above every horizon), light them where
// the sun is above the kNone horizon (no sweep direction), or a sweep.
enum class Kind { Night, AllLit, Flat, Swept };

struct Position {
  sweep::SunPosition sun;
  Kind kind = Kind::Night;
  sweep::Geometry geo;
  float tan_e = 0.0f;
  int swept = -1;  // index among the swept positions
};

// The sun positions in the whole-domain run's order: the day's intervals per declination, then the instant.
std::vector<Position> positions(const SunParams& p, const std::vector<double>& decls, int month, double hour,
                                glm::dvec2 max_grad, const Domain& whole) {
  std::vector<Position> all;
  auto add = [&](glm::dvec3 s, double weight) {
    Position q;
    q.sun = {s, weight};
    if (s.z > 0.0) {
      q.kind = Kind::AllLit;
      if (sweep::casts_shadows(max_grad, s)) {
        q.tan_e = sweep::sun_tangent(s);
        const auto geo = sweep::geometry(whole.resolution, whole.spacing, {s.x, s.y});
        q.kind = geo ? Kind::Swept : Kind::Flat;
        if (geo) q.geo = *geo;
      }
    }
    all.push_back(q);
  };
  const int steps = sweep::day_steps(p);
  for (const double decl : decls)
    for (int k = 0; k < steps; ++k)
      if (const auto sun = sweep::day_position(p, decl, k)) add(sun->s, sun->weight);
  add(sun_direction(p.latitude, declination_deg(month), hour), 1.0);
  int swept = 0;
  for (Position& q : all)
    if (q.kind == Kind::Swept) q.swept = swept++;
  return all;
}

// A tile's rectangle in a sweep's axes (a major, b minor), the part of it whose line samples it computes
// (a <= ca1, b_lo <= b0 <= cb1), and the points (a, b0) of line samples its border cells read.
struct Frame {
  int a_lo = 0, a_hi = 0, b_lo = 0, b_hi = 0, ca1 = 0, cb1 = 0;
  Frame(const SampleRect& r, const sweep::Geometry& g) {
    const glm::ivec2 lo = g.major_x ? r.lo : glm::ivec2(r.lo.y, r.lo.x);
    const glm::ivec2 hi = g.major_x ? r.hi : glm::ivec2(r.hi.y, r.hi.x);
    a_lo = lo.x, a_hi = hi.x, b_lo = lo.y, b_hi = hi.y;
    ca1 = a_hi == g.A - 1 ? a_hi : a_hi - 1;
    cb1 = b_hi == g.B - 1 ? b_hi : b_hi - 1;
  }
  int wa() const { return a_hi - a_lo + 1; }
  bool owns(int a, int b0) const { return a >= a_lo && a <= ca1 && b0 >= b_lo && b0 <= cb1; }

  // The points the border cells (a = a_hi, b = b_lo or b = b_hi) read: rows b_lo - 1, b_lo, b_hi - 1, b_hi over
  // a_lo..a_hi - 1, then column a_hi over b_lo - 1..b_hi.
  std::size_t ring_size() const {
    return 4 * static_cast<std::size_t>(wa()) + static_cast<std::size_t>(b_hi - b_lo + 2);
  }
  template <class Fn>
  void for_each_ring(Fn&& fn) const {
    for (const int b0 : {b_lo - 1, b_lo, b_hi - 1, b_hi})
      for (int a = a_lo; a < a_hi; ++a) fn(a, b0);
    for (int b0 = b_lo - 1; b0 <= b_hi; ++b0) fn(a_hi, b0);
  }
  std::size_t ring_index(int a, int b0) const {
    if (a == a_hi) return 4 * static_cast<std::size_t>(wa()) + static_cast<std::size_t>(b0 - (b_lo - 1));
    const int row = b0 == b_lo - 1 ? 0 : b0 == b_lo ? 1 : b0 == b_hi - 1 ? 2 : 3;
    return static_cast<std::size_t>(row) * static_cast<std::size_t>(wa()) + static_cast<std::size_t>(a - a_lo);
  }

  // The line samples it sends to its neighbors' border cells: its first column (b_lo..cb1), then its rows b_lo and
  // cb1 (a_lo..ca1).
  std::size_t sent_size() const {
    return static_cast<std::size_t>(cb1 - b_lo + 1) + 2 * static_cast<std::size_t>(ca1 - a_lo + 1);
  }
  template <class Fn>
  void for_each_sent(Fn&& fn) const {
    for (int b0 = b_lo; b0 <= cb1; ++b0) fn(a_lo, b0);
    for (const int b0 : {b_lo, cb1})
      for (int a = a_lo; a <= ca1; ++a) fn(a, b0);
  }
  // Where point (a, b0), which the tile owns, lies in what it sends; throws when it sends no such point.
  std::size_t sent_index(int a, int b0) const {
    const std::size_t nb = static_cast<std::size_t>(cb1 - b_lo + 1), na = static_cast<std::size_t>(ca1 - a_lo + 1);
    if (a == a_lo) return static_cast<std::size_t>(b0 - b_lo);
    if (b0 == b_lo) return nb + static_cast<std::size_t>(a - a_lo);
    if (b0 == cb1) return nb + na + static_cast<std::size_t>(a - a_lo);
    refuse("a border cell reads a line sample inside another tile");
  }
};

// The hull of a line's samples so far, with the step of each point (a point's distance away from the sun follows
// from its step and line: it travels as the step).
struct Hull {
  std::vector<double> u, z;
  std::vector<std::int32_t> step;
  std::size_t n = 0;
  int last_step = -1;
  bool started = false;
};

class SunTile : public TileGraphTile {
 public:
  SunTile(HeightfieldPtr in, const SunParams& p, std::vector<int> months, int month, double hour, const Domain& whole)
      : in_(std::move(in)),
        p_(p),
        months_(std::move(months)),
        month_(month),
        hour_(hour),
        whole_(whole),
        rect_(rect_of(in_->domain, whole)) {}

  std::string message(int round) override {
    std::string out;
    bytes::put(out, rect_);
    if (round == 0) {
      bytes::put(out, sweep::largest_steps(*in_));
      erosion::Bands(rect_, whole_.resolution, 1).for_each([&](glm::ivec2 s) { bytes::put(out, height(s)); });
      return out;
    }
    if (!grid_) refuse("round " + std::to_string(round) + " before the tiling");
    if (round < grid_->nx() + grid_->ny()) {
      sweep_round(round - 1, out);
      return out;
    }
    bytes::put(out, static_cast<std::int32_t>(swept_.size()));
    for (const Swept& w : swept_) bytes::put(out, static_cast<std::int32_t>(w.pos->geo.major_x));
    for (const Swept& w : swept_)
      out.append(reinterpret_cast<const char*>(w.sent.data()), w.sent.size() * sizeof(float));
    return out;
  }

  void answer(int round, std::string_view in) override {
    if (round > 0 && !grid_) refuse("round " + std::to_string(round) + " before the tiling");
    if (round == 0) {
      take_setup(in);
    } else if (round < grid_->nx() + grid_->ny()) {
      while (!in.empty()) {
        const auto e = bytes::take<std::int32_t>(in, kWhat), line = bytes::take<std::int32_t>(in, kWhat);
        const auto n = bytes::take<std::int32_t>(in, kWhat);
        if (e < 0 || static_cast<std::size_t>(e) >= swept_.size() || n < 1 ||
            static_cast<std::size_t>(n) > in.size() / kHullPointBytes)
          refuse("a damaged line hull");
        const sweep::Geometry& g = swept_[static_cast<std::size_t>(e)].pos->geo;
        Hull h;
        h.n = static_cast<std::size_t>(n);
        h.u.resize(h.n + 1), h.z.resize(h.n + 1), h.step.resize(h.n + 1);
        for (std::size_t k = 0; k < h.n; ++k) {
          h.step[k] = bytes::take<std::int32_t>(in, kWhat);
          if (h.step[k] < 0 || h.step[k] >= g.A) refuse("a damaged line hull");
          h.u[k] = sweep::line_distance(g, sweep::crossing(g, h.step[k]), line);
        }
        for (std::size_t k = 0; k < h.n; ++k) h.z[k] = bytes::take<double>(in, kWhat);
        swept_[static_cast<std::size_t>(e)].incoming.emplace(line, std::move(h));
      }
    } else {
      for (Swept& w : swept_) {
        const Frame f(rect_, w.pos->geo);
        f.for_each_ring([&](int a, int b0) {
          if (!f.owns(a, b0) && b0 >= 0 && b0 <= w.pos->geo.B - 1)
            w.ring[f.ring_index(a, b0)] = bytes::take<float>(in, kWhat);
        });
      }
    }
    if (!in.empty()) refuse("bytes left over");
  }

  std::vector<PortValue> outputs() override {
    const Domain& d = in_->domain;
    const std::size_t n = d.sample_count();
    tbb::parallel_for(std::size_t(0), swept_.size(), [&](std::size_t e) { light_frame(swept_[e]); });
    const auto hours_img = sweep::month_image(d, months_), irr_img = sweep::month_image(d, months_);
    const std::vector<double> decls = sweep::declinations(months_);
    const std::size_t nm = months_.size();
    std::vector<float> hours(n), irr(n);
    std::size_t next = 0;
    // The cells lit at position q, as the whole-domain run adds them (every cell from one place, in any order).
    auto accumulate = [&](const Position& q, float* h, float* r) {
      if (q.kind == Kind::Night) return;
      const sweep::Light light(q.sun.s, q.sun.weight, p_.irradiance);
      for (std::size_t c = 0; c < n; ++c)
        if (q.kind == Kind::AllLit || (q.kind == Kind::Flat && q.tan_e > sweep::kNone) ||
            (q.kind == Kind::Swept && lit(swept_[static_cast<std::size_t>(q.swept)], c)))
          light.add(normals_[c], h ? h + c : nullptr, r ? r + c : nullptr);
    };
    const int steps = sweep::day_steps(p_);
    for (const double decl : decls) {
      std::fill(hours.begin(), hours.end(), 0.0f);
      std::fill(irr.begin(), irr.end(), 0.0f);
      for (int k = 0; k < steps; ++k)
        if (sweep::day_position(p_, decl, k)) accumulate(positions_[next++], hours.data(), irr.data());
      for (std::size_t c = 0; c < nm; ++c) {
        if (declination_deg(months_[c]) != decl) continue;
        for (std::size_t q = 0; q < n; ++q) {
          hours_img->data[q * nm + c] = hours[q];
          irr_img->data[q * nm + c] = irr[q] / 24.0f;
        }
      }
    }
    auto lit_map = std::make_shared<Heightfield>(d), direct = std::make_shared<Heightfield>(d);
    accumulate(positions_[next++], lit_map->data.data(), direct->data.data());
    return {ImagePtr(hours_img), ImagePtr(irr_img), HeightfieldPtr(lit_map), HeightfieldPtr(direct)};
  }

 private:
  // A swept sun position on this tile: its lit interior cells, the line samples its border cells read, and those
  // it sends.
  struct Swept {
    const Position* pos = nullptr;
    int turn = 0;                    // the wavefront round - 1 in which the tile sweeps it
    std::vector<std::uint64_t> lit;  // interior cells, by tile sample index
    std::vector<float> ring, sent;
    std::unordered_map<int, Hull> incoming;  // by line
  };

  float height(glm::ivec2 s) const { return in_->at(s.x - rect_.lo.x, s.y - rect_.lo.y); }

  void take_setup(std::string_view& in) {
    const auto steps = bytes::take<glm::dvec2>(in, kWhat);
    Grid g;
    for (auto* v : {&g.xs, &g.ys}) {
      const auto count = bytes::take<std::int32_t>(in, kWhat);
      if (count < 1 || static_cast<std::size_t>(count) > in.size() / sizeof(std::int32_t)) refuse("a damaged tiling");
      for (std::int32_t k = 0; k < count; ++k) v->push_back(bytes::take<std::int32_t>(in, kWhat));
    }
    grid_ = g;
    tile_ = g.index(rect_);
    // The heights one sample around the tile (within the domain), for the normals.
    const glm::ivec2 whole = whole_.resolution;
    const glm::ivec2 lo = glm::max(rect_.lo - 1, glm::ivec2(0)), hi = glm::min(rect_.hi + 1, whole - 1);
    Domain pd = in_->domain;
    pd.first += lo - rect_.lo;
    pd.resolution = hi - lo + 1;
    Heightfield padded(pd);
    for (int j = rect_.lo.y; j <= rect_.hi.y; ++j)
      for (int i = rect_.lo.x; i <= rect_.hi.x; ++i) padded.at(i - lo.x, j - lo.y) = height({i, j});
    erosion::for_each_halo(rect_, whole, 1,
                           [&](glm::ivec2 s) { padded.at(s.x - lo.x, s.y - lo.y) = bytes::take<float>(in, kWhat); });
    normals_.resize(in_->domain.sample_count());
    for (int j = rect_.lo.y; j <= rect_.hi.y; ++j)
      for (int i = rect_.lo.x; i <= rect_.hi.x; ++i)
        normals_[in_->index(i - rect_.lo.x, j - rect_.lo.y)] = sweep::normal_at(padded, i - lo.x, j - lo.y);
    const glm::dvec2 max_grad{steps.x / std::abs(whole_.spacing.x), steps.y / std::abs(whole_.spacing.y)};
    positions_ = positions(p_, sweep::declinations(months_), month_, hour_, max_grad, whole_);
    swept_.clear();
    for (const Position& q : positions_) {
      if (q.kind != Kind::Swept) continue;
      Swept w;
      w.pos = &q;
      const glm::dvec2 d{q.sun.s.x, q.sun.s.y};
      w.turn = (d.x > 0.0 ? g.nx() - 1 - tile_.x : tile_.x) + (d.y > 0.0 ? g.ny() - 1 - tile_.y : tile_.y);
      swept_.push_back(std::move(w));
    }
  }

  // Sweeps every position whose turn is `turn`, appending the hulls of the lines leaving the tile.
  void sweep_round(int turn, std::string& out) {
    std::vector<std::size_t> now;
    for (std::size_t e = 0; e < swept_.size(); ++e)
      if (swept_[e].turn == turn) now.push_back(e);
    std::vector<std::string> leaving(now.size());
    tbb::parallel_for(std::size_t(0), now.size(), [&](std::size_t k) { sweep_one(now[k], leaving[k]); });
    for (const std::string& s : leaving) out += s;
  }

  // The tile's part of sweep e: its line samples from the hulls of the lines entering it, its interior cells, the
  // line samples of its frame; the hulls of the lines leaving it go to `out`.
  void sweep_one(std::size_t e, std::string& out) {
    Swept& w = swept_[e];
    const sweep::Geometry& g = w.pos->geo;
    const Frame f(rect_, g);
    const int hb = f.b_hi - f.b_lo + 2;  // scratch rows: b0 = b_lo - 1 .. b_hi
    std::vector<float> T(static_cast<std::size_t>(f.wa()) * static_cast<std::size_t>(hb), sweep::kOutside);
    auto at = [&](int a, int b0) -> float& {
      return T[static_cast<std::size_t>(a - f.a_lo) * static_cast<std::size_t>(hb) +
               static_cast<std::size_t>(b0 - (f.b_lo - 1))];
    };
    auto z = [&](int a, int b) { return g.major_x ? height({a, b}) : height({b, a}); };
    const int s0 = std::min(g.column(f.a_lo), g.column(f.ca1)), s1 = std::max(g.column(f.a_lo), g.column(f.ca1));
    const int boff0 = sweep::crossing(g, s0).boff, boff1 = sweep::crossing(g, s1).boff;
    const int lmin = f.b_lo - std::max(boff0, boff1), lmax = f.cb1 - std::min(boff0, boff1);
    std::vector<Hull> hulls(static_cast<std::size_t>(lmax - lmin + 1));
    for (int s = s0; s <= s1; ++s) {
      const sweep::Crossing c = sweep::crossing(g, s);
      for (int b0 = f.b_lo; b0 <= f.cb1; ++b0) {
        if (!sweep::on_grid(g, c, b0)) continue;
        const int l = b0 - c.boff;
        Hull& h = hulls[static_cast<std::size_t>(l - lmin)];
        if (!h.started) start_line(w, g, s, l, h);
        if (h.u.size() < h.n + 1) h.u.resize(2 * h.n + 8), h.z.resize(2 * h.n + 8), h.step.resize(2 * h.n + 8);
        const double zp = sweep::line_height(c, z(c.a, b0), c.f == 0.0 ? 0.0f : z(c.a, b0 + 1));
        at(c.a, b0) = sweep::hull_step(h.u.data(), h.z.data(), h.n, sweep::line_distance(g, c, l), zp);
        h.step[h.n - 1] = s;
        h.last_step = s;
      }
    }
    w.incoming.clear();
    // The lines leaving the tile, to the tile of their next sample.
    for (std::size_t k = 0; k < hulls.size(); ++k) {
      const Hull& h = hulls[k];
      if (!h.started || h.last_step + 1 >= g.A) continue;
      const int l = lmin + static_cast<int>(k);
      const sweep::Crossing c = sweep::crossing(g, h.last_step + 1);
      const int b0 = l + c.boff;
      if (!sweep::on_grid(g, c, b0)) continue;
      const int ta = Grid::owner(g.major_x ? grid_->xs : grid_->ys, c.a);
      const int tb = Grid::owner(g.major_x ? grid_->ys : grid_->xs, b0);
      const glm::ivec2 to = g.major_x ? glm::ivec2(ta, tb) : glm::ivec2(tb, ta);
      for (const std::int32_t v :
           {to.x, to.y, static_cast<std::int32_t>(e), static_cast<std::int32_t>(l), static_cast<std::int32_t>(h.n)})
        bytes::put(out, v);
      out.append(reinterpret_cast<const char*>(h.step.data()), h.n * sizeof(std::int32_t));
      out.append(reinterpret_cast<const char*>(h.z.data()), h.n * sizeof(double));
    }
    // Interior cells (not on the last column or on the first or last row of the sweep) read only the tile's own
    // line samples.
    const std::size_t n = in_->domain.sample_count();
    w.lit.assign((n + 63) / 64, 0);
    for (int a = f.a_lo; a < f.a_hi; ++a) {
      const sweep::ColumnRead r = sweep::column_read(g, a);
      const int below = r.below + sweep::crossing(g, g.column(a)).boff;  // b0 of the line below, less b
      for (int b = f.b_lo + 1; b < f.b_hi; ++b) {
        const float t0 = at(a, b + below);
        if (w.pos->tan_e > sweep::blend(t0, r.frac > 0.0f ? at(a, b + below + 1) : t0, r.frac)) {
          const std::size_t c = cell(g, a, b);
          w.lit[c / 64] |= std::uint64_t(1) << (c % 64);
        }
      }
    }
    w.ring.assign(f.ring_size(), sweep::kOutside);
    f.for_each_ring([&](int a, int b0) {
      if (f.owns(a, b0)) w.ring[f.ring_index(a, b0)] = at(a, b0);
    });
    w.sent.clear();
    f.for_each_sent([&](int a, int b0) { w.sent.push_back(at(a, b0)); });
  }

  // Line l's hull at its first sample in the tile, step s: from the tile before it, or empty where the line enters
  // the grid here.
  static void start_line(Swept& w, const sweep::Geometry& g, int s, int l, Hull& h) {
    h.started = true;
    if (s == 0) return;
    const sweep::Crossing c = sweep::crossing(g, s - 1);
    if (!sweep::on_grid(g, c, l + c.boff)) return;
    const auto it = w.incoming.find(l);
    if (it == w.incoming.end()) refuse("no hull came for a line entering the tile");
    h = std::move(it->second);
    h.started = true;
  }

  std::size_t cell(const sweep::Geometry& g, int a, int b) const {
    const glm::ivec2 s = g.major_x ? glm::ivec2(a, b) : glm::ivec2(b, a);
    return in_->index(s.x - rect_.lo.x, s.y - rect_.lo.y);
  }

  static bool lit(const Swept& w, std::size_t c) { return (w.lit[c / 64] >> (c % 64)) & 1; }

  // The lit bits of the cells on the frame (the sweep's last column, first and last rows), from the line samples
  // either side of them.
  void light_frame(Swept& w) const {
    if (w.lit.empty()) refuse("a sun position was never swept on the tile");
    const sweep::Geometry& g = w.pos->geo;
    const Frame f(rect_, g);
    auto light = [&](int a, int b) {
      const sweep::ColumnRead r = sweep::column_read(g, a);
      const int b0 = b + r.below + sweep::crossing(g, g.column(a)).boff;
      const float t0 = w.ring[f.ring_index(a, b0)];
      if (w.pos->tan_e > sweep::blend(t0, r.frac > 0.0f ? w.ring[f.ring_index(a, b0 + 1)] : t0, r.frac)) {
        const std::size_t c = cell(g, a, b);
        w.lit[c / 64] |= std::uint64_t(1) << (c % 64);
      }
    };
    for (int a = f.a_lo; a < f.a_hi; ++a) {
      light(a, f.b_lo);
      if (f.b_hi != f.b_lo) light(a, f.b_hi);
    }
    for (int b = f.b_lo; b <= f.b_hi; ++b) light(f.a_hi, b);
  }

  HeightfieldPtr in_;
  SunParams p_;
  std::vector<int> months_;
  int month_;
  double hour_;
  Domain whole_;
  SampleRect rect_;
  std::optional<Grid> grid_;
  glm::ivec2 tile_{0, 0};
  std::vector<glm::vec3> normals_;
  std::vector<Position> positions_;
  std::vector<Swept> swept_;
};

class SunAcrossTiles : public TileGraphAlgorithm {
 public:
  SunAcrossTiles(const SunParams& p, std::vector<int> months, int month, double hour, const Domain& whole)
      : p_(p), months_(std::move(months)), month_(month), hour_(hour), whole_(whole) {}

  int rounds() const override { return 3; }  // on one tile; nx + ny + 1 on nx x ny tiles

  bool another_round(int round, const std::vector<std::string>& messages) const override {
    const Grid g = grid_of(rects_of(messages), whole_.resolution);
    return round < g.nx() + g.ny();
  }

  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    const auto* h = inputs.empty() ? nullptr : std::get_if<HeightfieldPtr>(&inputs[0]);
    if (!h || !*h) throw std::invalid_argument("sun across tiles needs a heightfield input");
    return std::make_unique<SunTile>(*h, p_, months_, month_, hour_, whole_);
  }

  std::vector<std::string> solve(int round, const std::vector<std::string>& messages) const override {
    const std::vector<SampleRect> rects = rects_of(messages);
    const Grid g = grid_of(rects, whole_.resolution);
    const std::size_t count = messages.size();
    std::vector<std::size_t> tile_at(count);  // message of each tile, row-major over the grid
    for (std::size_t t = 0; t < count; ++t) {
      const glm::ivec2 k = g.index(rects[t]);
      tile_at[static_cast<std::size_t>(k.y) * static_cast<std::size_t>(g.nx()) + static_cast<std::size_t>(k.x)] = t;
    }
    std::vector<std::string> answers(count);
    if (round == 0) return setup(messages, rects, g);
    if (round < g.nx() + g.ny()) {
      // Every hull to the tile it enters.
      for (std::size_t t = 0; t < count; ++t) {
        std::string_view in(messages[t]);
        in.remove_prefix(sizeof(SampleRect));
        while (!in.empty()) {
          const auto tx = bytes::take<std::int32_t>(in, kWhat), ty = bytes::take<std::int32_t>(in, kWhat);
          const auto e = bytes::take<std::int32_t>(in, kWhat), line = bytes::take<std::int32_t>(in, kWhat);
          const auto n = bytes::take<std::int32_t>(in, kWhat);
          if (tx < 0 || tx >= g.nx() || ty < 0 || ty >= g.ny() || n < 1 ||
              static_cast<std::size_t>(n) > in.size() / kHullPointBytes)
            refuse("a damaged line hull");
          std::string& to = answers[tile_at[static_cast<std::size_t>(ty) * static_cast<std::size_t>(g.nx()) +
                                            static_cast<std::size_t>(tx)]];
          for (const std::int32_t v : {e, line, n}) bytes::put(to, v);
          const std::size_t hull_bytes = static_cast<std::size_t>(n) * kHullPointBytes;
          to.append(in.substr(0, hull_bytes));
          in.remove_prefix(hull_bytes);
        }
      }
      return answers;
    }
    return frames(messages, rects, g, tile_at);
  }

 private:
  // Round 0: the largest steps over all tiles, the tiling, and each tile's halo one sample deep.
  std::vector<std::string> setup(const std::vector<std::string>& messages, const std::vector<SampleRect>& rects,
                                 const Grid& g) const {
    const std::size_t count = messages.size();
    glm::dvec2 steps{0.0, 0.0};
    std::vector<const char*> bands(count);
    const auto plan = plans_.get(rects, whole_.resolution, 1, kWhat);
    for (std::size_t t = 0; t < count; ++t) {
      std::string_view in(messages[t]);
      in.remove_prefix(sizeof(SampleRect));
      const auto s = bytes::take<glm::dvec2>(in, kWhat);
      steps = glm::max(steps, s);  // an infinite step (a NaN height) wins
      if (in.size() != plan->stride[t]) refuse("truncated bytes");
      bands[t] = in.data();
    }
    std::vector<std::string> answers(count);
    for (std::size_t u = 0; u < count; ++u) {
      std::string& out = answers[u];
      bytes::put(out, steps);
      for (const auto* v : {&g.xs, &g.ys}) {
        bytes::put(out, static_cast<std::int32_t>(v->size()));
        for (const int x : *v) bytes::put(out, static_cast<std::int32_t>(x));
      }
      erosion::append_halo(out, *plan, u, 1, bands);
    }
    return answers;
  }

  // Last round: each tile's border cells' line samples from the tiles that computed them.
  std::vector<std::string> frames(const std::vector<std::string>& messages, const std::vector<SampleRect>& rects,
                                  const Grid& g, const std::vector<std::size_t>& tile_at) const {
    const std::size_t count = messages.size();
    std::vector<std::vector<int>> major(count);           // per tile, per sweep: whether x is the major axis
    std::vector<std::vector<std::size_t>> starts(count);  // per tile, per sweep: where its values start
    for (std::size_t t = 0; t < count; ++t) {
      std::string_view in(messages[t]);
      in.remove_prefix(sizeof(SampleRect));
      const auto n = bytes::take<std::int32_t>(in, kWhat);
      if (n < 0 || static_cast<std::size_t>(n) > in.size() / sizeof(std::int32_t)) refuse("truncated bytes");
      for (std::int32_t k = 0; k < n; ++k) major[t].push_back(bytes::take<std::int32_t>(in, kWhat));
      if (t > 0 && major[t] != major[0]) refuse("the tiles swept different suns");
      std::size_t at = messages[t].size() - in.size();
      for (const int mx : major[t]) {
        starts[t].push_back(at);
        at += Frame(rects[t], axes(mx != 0)).sent_size() * sizeof(float);
      }
      if (at != messages[t].size()) refuse("truncated bytes");
    }
    std::vector<std::string> answers(count);
    for (std::size_t u = 0; u < count; ++u)
      for (std::size_t e = 0; e < major[u].size(); ++e) {
        const sweep::Geometry geo = axes(major[u][e] != 0);
        const Frame f(rects[u], geo);
        f.for_each_ring([&](int a, int b0) {
          if (f.owns(a, b0) || b0 < 0 || b0 > geo.B - 1) return;
          const int ta = Grid::owner(geo.major_x ? g.xs : g.ys, a), tb = Grid::owner(geo.major_x ? g.ys : g.xs, b0);
          const glm::ivec2 k = geo.major_x ? glm::ivec2(ta, tb) : glm::ivec2(tb, ta);
          const std::size_t t =
              tile_at[static_cast<std::size_t>(k.y) * static_cast<std::size_t>(g.nx()) + static_cast<std::size_t>(k.x)];
          const std::size_t at = starts[t][e] + Frame(rects[t], geo).sent_index(a, b0) * sizeof(float);
          answers[u].append(messages[t].data() + at, sizeof(float));
        });
      }
    return answers;
  }

  // The axes of a sweep along x or y (all a Frame needs).
  sweep::Geometry axes(bool major_x) const {
    sweep::Geometry geo;
    geo.major_x = major_x;
    geo.A = major_x ? whole_.resolution.x : whole_.resolution.y;
    geo.B = major_x ? whole_.resolution.y : whole_.resolution.x;
    return geo;
  }

  SunParams p_;
  std::vector<int> months_;
  int month_;
  double hour_;
  Domain whole_;
  mutable erosion::HaloPlanCache plans_;
};

// Every parameter value runs across the tiles; values the whole-domain node refuses, and domains narrower than two
// samples, stay on the whole domain (whose node reports why).
const bool kSunRegistered = register_tile_graph("SunIllumination", [](const ParamView& v, const Domain& whole) {
  if (whole.resolution.x < 2 || whole.resolution.y < 2) return std::unique_ptr<TileGraphAlgorithm>();
  SunParams p;
  p.latitude = v.get<double>("latitude");
  p.time_step = v.get<double>("time_step");
  p.irradiance = v.get<double>("irradiance");
  const int month = calendar::month_of_day(static_cast<int>(v.get<std::int64_t>("day_of_year")));
  std::vector<int> months;
  if (v.get<bool>("all_months"))
    for (int m = 1; m <= 12; ++m) months.push_back(m);
  else
    months.push_back(month);
  return sun_across_tiles(p, months, month, v.get<double>("hour"), whole);
});

}  // namespace

std::unique_ptr<TileGraphAlgorithm> sun_across_tiles(const SunParams& p, std::vector<int> months, int month,
                                                     double hour, const Domain& whole) {
  sweep::check_params(p);
  return std::make_unique<SunAcrossTiles>(p, std::move(months), month, hour, whole);
}

}  // namespace orogen::climate
