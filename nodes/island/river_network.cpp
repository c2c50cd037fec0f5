#include "nodes/island/river_network.h"

#include <algorithm>
#include <limits>
#include <queue>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "graph/exec_context.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/smoothstep.h"
#include "nodes/common/work_poll.h"
#include "nodes/island/cell_index.h"
#include "nodes/island/island.h"
#include "nodes/island/island_random.h"

namespace orogen::island {
namespace {

double cross(glm::dvec2 a, glm::dvec2 b) { return a.x * b.y - a.y * b.x; }

int orient(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c) {
  const double v = cross(b - a, c - a);
  return (v > 0.0) - (v < 0.0);
}

bool on_segment(glm::dvec2 a, glm::dvec2 b, glm::dvec2 p) {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}

// Segments ab and cd meet (touching included), unless they only share an endpoint.
bool segments_meet(glm::dvec2 a, glm::dvec2 b, glm::dvec2 c, glm::dvec2 d) {
  const bool shared = a == c || a == d || b == c || b == d;
  const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (shared) {
    // Sharing an endpoint is allowed unless the segments overlap along a line.
    if (o1 == 0 && o2 == 0) {
      const glm::dvec2 u = b - a, v = d - c;
      return glm::dot(u, v) * ((a == c || b == d) ? 1.0 : -1.0) > 0.0;
    }
    return false;
  }
  if (o1 != o2 && o3 != o4) return true;
  if (o1 == 0 && on_segment(a, b, c)) return true;
  if (o2 == 0 && on_segment(a, b, d)) return true;
  if (o3 == 0 && on_segment(c, d, a)) return true;
  if (o4 == 0 && on_segment(c, d, b)) return true;
  return false;
}

glm::dvec2 bezier(glm::dvec2 p0, glm::dvec2 p1, glm::dvec2 p2, double t) {
  const double u = 1.0 - t;
  return u * u * p0 + 2.0 * u * t * p1 + t * t * p2;
}

// Uniform buckets of segments.
struct SegmentIndex {
  glm::dvec2 lo{0.0};
  double cell = 1.0;
  int gw = 1, gh = 1;
  std::vector<std::vector<std::pair<glm::dvec2, glm::dvec2>>> buckets;

  SegmentIndex(glm::dvec2 lo_, glm::dvec2 size, double cell_) : lo(lo_) {
    cell = std::max(cell_, 1e-9);
    // Clamped in double before the cast (a tiny cell over a large size would overflow an int).
    gw = static_cast<int>(std::clamp(std::ceil(size.x / cell), 1.0, 2048.0));
    gh = static_cast<int>(std::clamp(std::ceil(size.y / cell), 1.0, 2048.0));
    cell = std::max(size.x / gw, size.y / gh);
    buckets.resize(static_cast<std::size_t>(gw) * static_cast<std::size_t>(gh));
  }
  glm::ivec2 bucket(glm::dvec2 p) const {
    return {static_cast<int>(std::clamp(std::floor((p.x - lo.x) / cell), 0.0, double(gw - 1))),
            static_cast<int>(std::clamp(std::floor((p.y - lo.y) / cell), 0.0, double(gh - 1)))};
  }
  template <class Fn>
  void for_buckets(glm::dvec2 a, glm::dvec2 b, Fn&& fn) {
    const glm::ivec2 i0 = bucket(glm::min(a, b)), i1 = bucket(glm::max(a, b));
    for (int y = i0.y; y <= i1.y; ++y)
      for (int x = i0.x; x <= i1.x; ++x) fn(buckets[static_cast<std::size_t>(y * gw + x)]);
  }
  void insert(glm::dvec2 a, glm::dvec2 b) {
    for_buckets(a, b, [&](auto& list) { list.emplace_back(a, b); });
  }
  bool crosses(glm::dvec2 a, glm::dvec2 b, WorkPoll& poll) {
    bool hit = false;
    for_buckets(a, b, [&](auto& list) {
      poll(1 + static_cast<std::int64_t>(list.size()));
      for (const auto& [c, d] : list)
        if (!hit && segments_meet(a, b, c, d)) hit = true;
    });
    return hit;
  }
};

}  // namespace

Curves river_network(const RiverNetworkParams& p, const Heightfield* mask, const ExecContext* ctx) {
  if (!(p.size.x > 0.0 && p.size.y > 0.0))
    throw NodeError("RiverNetwork: the map size must be positive (parameter 'size')");
  const glm::dvec2 lo = p.min_corner, hi = p.min_corner + p.size;
  const double area_km2 = p.size.x * p.size.y * 1e-6;
  const double wanted = p.density * area_km2;
  if (wanted > 2e6) throw NodeError("RiverNetwork: more than 2 million inner points: lower 'density' or 'size'");
  auto land = [&](glm::dvec2 q) {
    if (!mask) return true;
    return mask->sample_world(q.x, q.y) >= 0.5f;
  };

  // Outlets.
  std::vector<glm::dvec2> pts;
  if (!mask) {
    const double perimeter = 2.0 * (p.size.x + p.size.y);
    for (int k = 0; k < p.outlets; ++k) {
      double s = unit_hash(p.seed, 0x4f55544cull, static_cast<std::uint64_t>(k)) * perimeter;
      glm::dvec2 q;
      if (s < p.size.x)
        q = {lo.x + s, lo.y};
      else if ((s -= p.size.x) < p.size.y)
        q = {hi.x, lo.y + s};
      else if ((s -= p.size.y) < p.size.x)
        q = {hi.x - s, hi.y};
      else
        q = {lo.x, hi.y - (s - p.size.x)};
      pts.push_back(q);
    }
  } else {
    // Coast samples: land with a water 4-neighbour, inside the rectangle.
    std::vector<glm::dvec2> coast;
    const Domain& d = mask->domain;
    for (int j = 0; j < d.height(); ++j)
      for (int i = 0; i < d.width(); ++i) {
        if (!(mask->at(i, j) >= 0.5f)) continue;
        const glm::dvec2 q = d.position(i, j);
        if (q.x < lo.x || q.y < lo.y || q.x > hi.x || q.y > hi.y) continue;
        bool wet = false;
        for (const auto& [di, dj] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
          const int a = i + di, b = j + dj;
          if (a >= 0 && b >= 0 && a < d.width() && b < d.height() && !(mask->at(a, b) >= 0.5f)) wet = true;
        }
        if (wet) coast.push_back(q);
      }
    for (int k = 0; k < p.outlets && !coast.empty(); ++k) {
      const auto at = std::min(
          coast.size() - 1, static_cast<std::size_t>(unit_hash(p.seed, 0x4f55544cull, static_cast<std::uint64_t>(k)) *
                                                     static_cast<double>(coast.size())));
      pts.push_back(coast[at]);
      coast.erase(coast.begin() + static_cast<std::ptrdiff_t>(at));
    }
  }
  const int roots = static_cast<int>(pts.size());
  if (wanted >= 1.0)
    for (const glm::dvec2& q :
         poisson_sites(lo, p.size, static_cast<int>(std::ceil(wanted)), hash64(p.seed, 0x494e4e52ull, 0), ctx))
      if (land(q)) pts.push_back(q);
  const int n = static_cast<int>(pts.size());

  // Point buckets for nearest-candidate queries: about 4 inner points per bucket, as square as the aspect
  // ratio allows (at most 2048 a side), whatever max_length is; candidates come ring by ring (below).
  const double inner = std::max(1.0, static_cast<double>(n - roots));
  const double target = std::clamp(inner / 4.0, 1.0, 2048.0 * 2048.0);
  const int gw = static_cast<int>(std::clamp(std::round(std::sqrt(target * p.size.x / p.size.y)), 1.0, 2048.0));
  const int gh = static_cast<int>(std::clamp(std::round(target / gw), 1.0, 2048.0));
  const glm::dvec2 bsize = p.size / glm::dvec2(gw, gh);
  std::vector<std::vector<int>> point_buckets(static_cast<std::size_t>(gw) * static_cast<std::size_t>(gh));
  auto cell_of = [](double u, int count) {
    const double f = std::floor(u);
    return !(f >= 0.0) ? 0 : f >= count - 1 ? count - 1 : static_cast<int>(f);
  };
  auto bucket_of = [&](glm::dvec2 q) {
    return glm::ivec2(cell_of((q.x - lo.x) / bsize.x, gw), cell_of((q.y - lo.y) / bsize.y, gh));
  };
  for (int k = roots; k < n; ++k) {
    const glm::ivec2 b = bucket_of(pts[ix(k)]);
    point_buckets[static_cast<std::size_t>(b.y * gw + b.x)].push_back(k);
  }
  // Segment buckets a few point spacings wide (crossing tests then look at nearby segments only).
  const double spacing = std::sqrt(p.size.x * p.size.y / inner);
  const double segment_cell = std::max(std::min(p.max_length, 4.0 * spacing), 1e-6);

  SegmentIndex segments(lo - glm::dvec2(1.0), p.size + glm::dvec2(2.0), segment_cell);
  std::vector<int> parent(ix(n), -1);
  std::vector<char> used(ix(n), 0);
  std::vector<glm::dvec2> control(ix(n));      // P1 of the curve ending at point k
  std::vector<glm::dvec2> end_tangent(ix(n));  // unit tangent at P2 of that curve (growth direction)
  std::vector<char> continued(ix(n), 0);       // a child already continues the tangent at this point
  std::vector<char> smooth(ix(n), 0);          // the curve to this point continues its parent's tangent
  std::vector<int> order;                      // points in the order they joined
  const int samples = std::max(1, p.samples);
  std::vector<int> pool;
  for (int k = 0; k < roots; ++k) {
    used[ix(k)] = 1;
    pool.push_back(k);
  }

  // Candidates in increasing (distance, index), as a sort of every unused point within max_length would give
  // them, but lazily: rings of buckets around the pool point are scanned only while a nearer point could
  // still lie in them, so a point joined from nearby costs a few buckets, not a scan and sort of all points.
  using Candidate = std::pair<double, int>;
  std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> candidates;
  std::vector<glm::dvec2> poly(static_cast<std::size_t>(samples) + 1);
  std::uint64_t draw = 0;
  WorkPoll poll(ctx);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (std::size_t iter = 1; !pool.empty(); ++iter) {
    poll();
    if (ctx && (iter & 255) == 0) ctx->progress(0.1 + 0.8 * static_cast<double>(order.size()) / std::max(1, n - roots));
    const std::size_t slot =
        std::min(pool.size() - 1,
                 static_cast<std::size_t>(unit_hash(p.seed, 0x504f4f4cull, draw++) * static_cast<double>(pool.size())));
    const int k = pool[slot];
    const glm::dvec2 a = pts[ix(k)];
    candidates = {};
    const glm::ivec2 b = bucket_of(a);
    const int max_ring = std::max({b.x, gw - 1 - b.x, b.y, gh - 1 - b.y});
    int next_ring = 0;
    // Lower bound of the distance from a to the points of ring r (r columns or r rows away), counting only
    // the directions in which the grid goes on; +inf past the grid.
    const auto ring_bound = [&](int r) {
      if (r > max_ring) return kInf;
      if (r == 0) return 0.0;
      const bool columns = b.x - r >= 0 || b.x + r < gw, rows = b.y - r >= 0 || b.y + r < gh;
      return std::min(columns ? (r - 1) * bsize.x : kInf, rows ? (r - 1) * bsize.y : kInf);
    };
    const auto scan = [&](int x, int y) {
      const auto& list = point_buckets[static_cast<std::size_t>(y * gw + x)];
      poll(1 + static_cast<std::int64_t>(list.size()));
      for (int c : list) {
        if (used[ix(c)]) continue;
        const double d = glm::length(pts[ix(c)] - a);
        if (d <= p.max_length && d > 0.0) candidates.emplace(d, c);
      }
    };
    const auto scan_ring = [&](int r) {
      const int x0 = std::max(b.x - r, 0), x1 = std::min(b.x + r, gw - 1);
      if (b.y - r >= 0)
        for (int x = x0; x <= x1; ++x) scan(x, b.y - r);
      if (r == 0) return;
      if (b.y + r < gh)
        for (int x = x0; x <= x1; ++x) scan(x, b.y + r);
      const int y0 = std::max(b.y - r + 1, 0), y1 = std::min(b.y + r - 1, gh - 1);
      if (b.x - r >= 0)
        for (int y = y0; y <= y1; ++y) scan(b.x - r, y);
      if (b.x + r < gw)
        for (int y = y0; y <= y1; ++y) scan(b.x + r, y);
    };
    // The next candidate: final once it is nearer than anything an unscanned ring can hold.
    const auto next_candidate = [&](Candidate& out) {
      for (;;) {
        const double bound = ring_bound(next_ring);
        if (bound > p.max_length) break;  // no unscanned ring holds a point within max_length
        if (!candidates.empty() && candidates.top().first < bound) break;
        scan_ring(next_ring++);
      }
      if (candidates.empty()) return false;
      out = candidates.top();
      candidates.pop();
      return true;
    };
    bool accepted = false;
    for (Candidate cand; next_candidate(cand);) {
      const auto [dist, c] = cand;
      const glm::dvec2 e = pts[ix(c)];
      // Control point: continue the incoming tangent, or bend the chord by a hashed offset.
      glm::dvec2 p1;
      bool cont = false;
      if (k >= roots && !continued[ix(k)]) {
        const glm::dvec2 t = end_tangent[ix(k)];
        if (glm::dot(t, (e - a) / dist) > std::cos(75.0 * 3.14159265358979 / 180.0)) {
          p1 = a + t * (0.5 * dist);
          cont = true;
        }
      }
      if (!cont) {
        const glm::dvec2 chord = e - a, normal(-chord.y, chord.x);
        const double off = (2.0 * unit_hash(p.seed, 0x42454e44ull, static_cast<std::uint64_t>(c)) - 1.0) * p.meander;
        p1 = 0.5 * (a + e) + off * normal;
      }
      for (int s = 0; s <= samples; ++s)
        poly[ix(s)] = s == samples ? e : (s == 0 ? a : bezier(a, p1, e, static_cast<double>(s) / samples));
      bool ok = true;
      for (int s = 0; s < samples && ok; ++s) ok = !segments.crosses(poly[ix(s)], poly[ix(s + 1)], poll);
      for (int s = 1; s <= samples && ok; ++s)
        ok = poly[ix(s)].x >= lo.x && poly[ix(s)].y >= lo.y && poly[ix(s)].x <= hi.x && poly[ix(s)].y <= hi.y;
      if (ok && mask)
        for (int s = (k < roots ? 1 : 0); s <= samples && ok; ++s) ok = land(poly[ix(s)]);
      if (!ok) continue;
      for (int s = 0; s < samples; ++s) segments.insert(poly[ix(s)], poly[ix(s + 1)]);
      parent[ix(c)] = k;
      used[ix(c)] = 1;
      control[ix(c)] = p1;
      const glm::dvec2 tan = e - p1;
      end_tangent[ix(c)] = glm::length(tan) > 0.0 ? tan / glm::length(tan) : (e - a) / dist;
      if (cont) continued[ix(k)] = 1;
      smooth[ix(c)] = cont;
      pool.push_back(c);
      order.push_back(c);
      accepted = true;
      break;
    }
    if (!accepted) {
      pool[slot] = pool.back();
      pool.pop_back();
    }
  }

  // Sizes (leaves 1, else the sum of the children), in reverse joining order.
  std::vector<double> size(ix(n), 0.0);
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    const int c = *it;
    if (size[ix(c)] == 0.0) size[ix(c)] = 1.0;
    size[ix(parent[ix(c)])] += size[ix(c)];
  }
  // Heights and slopes, in joining order (a parent always joined before its children).
  std::vector<double> h(ix(n), 0.0), slope(ix(n), p.base_slope);
  for (int c : order) {
    const int q = parent[ix(c)];
    const double r = size[ix(c)] / std::max(size[ix(q)], 1.0);
    slope[ix(c)] = slope[ix(q)] - 4.0 * r * (r - 1.0) * p.slope_weight;
    h[ix(c)] = h[ix(q)] + glm::length(pts[ix(c)] - pts[ix(q)]) * slope[ix(c)];
  }

  Curves out;
  std::vector<int> curve_of(ix(n), -1);
  for (int c : order) curve_of[ix(c)] = static_cast<int>(out.curves.size()), out.curves.emplace_back();
  for (int c : order) {
    const int q = parent[ix(c)];
    Curve& curve = out.curves[ix(curve_of[ix(c)])];
    const glm::dvec2 a = pts[ix(q)], e = pts[ix(c)];
    const float width = static_cast<float>(p.river_width * std::pow(size[ix(c)], p.width_exponent));
    auto& sz = curve.attributes["size"];
    auto& sl = curve.attributes["slope"];
    auto& sm = curve.attributes["smooth_join"];
    for (int s = samples; s >= 0; --s) {  // upstream to downstream
      const double t = static_cast<double>(s) / samples;
      const glm::dvec2 xy = s == samples ? e : (s == 0 ? a : bezier(a, control[ix(c)], e, t));
      curve.points.emplace_back(static_cast<float>(xy.x), static_cast<float>(xy.y),
                                static_cast<float>(h[ix(q)] + t * (h[ix(c)] - h[ix(q)])));
      curve.width.push_back(width);
      sz.push_back(static_cast<float>(size[ix(c)]));
      sl.push_back(static_cast<float>(slope[ix(c)]));
      sm.push_back(smooth[ix(c)] ? 1.0f : 0.0f);
    }
    curve.parent = q >= roots ? curve_of[ix(q)] : -1;
  }
  return out;
}

CarveResult carve_rivers(const Heightfield& in, const Curves& rivers, const CarveParams& p, const ExecContext* ctx) {
  const Domain& d = in.domain;
  struct Seg {
    glm::dvec2 a, b;
    float za, zb, wa, wb;
    int curve;
  };
  std::vector<Seg> segs;
  double max_half_width = 0.0;
  for (std::size_t k = 0; k < rivers.curves.size(); ++k) {
    const Curve& c = rivers.curves[k];
    for (std::size_t s = 0; s + 1 < c.points.size(); ++s) {
      const float wa = s < c.width.size() ? c.width[s] : 0.0f, wb = s + 1 < c.width.size() ? c.width[s + 1] : wa;
      if (!std::isfinite(c.points[s].x + c.points[s].y + c.points[s].z + c.points[s + 1].x + c.points[s + 1].y +
                         c.points[s + 1].z + wa + wb))
        continue;
      segs.push_back({{c.points[s].x, c.points[s].y},
                      {c.points[s + 1].x, c.points[s + 1].y},
                      c.points[s].z,
                      c.points[s + 1].z,
                      std::max(0.0f, wa),
                      std::max(0.0f, wb),
                      static_cast<int>(k)});
      max_half_width = std::max(max_half_width, 0.5 * std::max(wa, wb));
    }
  }
  const double reach = std::max(p.radius, max_half_width);
  // Buckets over the domain's rectangle (segments outside it are clamped into the border buckets).
  const glm::dvec2 lo = d.min_corner() - reach, hi = d.max_corner() + reach;
  const double cell = std::max({reach, (hi.x - lo.x) / 1024.0, (hi.y - lo.y) / 1024.0, 1e-9});
  const int gw = std::clamp(static_cast<int>(std::ceil((hi.x - lo.x) / cell)), 1, 1024);
  const int gh = std::clamp(static_cast<int>(std::ceil((hi.y - lo.y) / cell)), 1, 1024);
  // Clamped before the cast: a segment far outside a tiny domain is billions of buckets away.
  auto bucket = [&](glm::dvec2 q) {
    return glm::ivec2(static_cast<int>(std::clamp(std::floor((q.x - lo.x) / cell), 0.0, double(gw - 1))),
                      static_cast<int>(std::clamp(std::floor((q.y - lo.y) / cell), 0.0, double(gh - 1))));
  };
  std::vector<std::vector<int>> buckets(static_cast<std::size_t>(gw) * static_cast<std::size_t>(gh));
  for (std::size_t s = 0; s < segs.size(); ++s) {
    const glm::ivec2 i0 = bucket(glm::min(segs[s].a, segs[s].b) - reach),
                     i1 = bucket(glm::max(segs[s].a, segs[s].b) + reach);
    if (static_cast<double>(i1.x - i0.x + 1) * (i1.y - i0.y + 1) > 1e6) continue;  // absurd geometry
    for (int y = i0.y; y <= i1.y; ++y)
      for (int x = i0.x; x <= i1.x; ++x) buckets[static_cast<std::size_t>(y * gw + x)].push_back(static_cast<int>(s));
  }

  CarveResult r;
  r.terrain = std::make_shared<Heightfield>(d);
  r.mask = std::make_shared<Heightfield>(d);
  const double spacing = std::max(1e-12, std::min(d.spacing.x, d.spacing.y));
  const double radius = std::max(p.radius, 1e-12);
  const auto row = [&](int j) {
    struct Near {
      int curve;
      double dist;
      float z, w;
    };
    std::vector<Near> nears;
    for (int i = 0; i < d.width(); ++i) {
      const glm::dvec2 x = d.position(i, j);
      const float h0 = in.at(i, j);
      nears.clear();
      if (!segs.empty()) {
        const glm::ivec2 b = bucket(x);
        for (int s : buckets[static_cast<std::size_t>(b.y * gw + b.x)]) {
          const Seg& g = segs[ix(s)];
          const glm::dvec2 ab = g.b - g.a;
          const double len2 = glm::dot(ab, ab);
          const double t = len2 > 0.0 ? std::clamp(glm::dot(x - g.a, ab) / len2, 0.0, 1.0) : 0.0;
          const double dist = glm::length(x - (g.a + t * ab));
          if (dist > reach) continue;
          const float z = static_cast<float>(g.za + t * (g.zb - g.za)),
                      w = static_cast<float>(g.wa + t * (g.wb - g.wa));
          auto it = std::find_if(nears.begin(), nears.end(), [&](const Near& n) { return n.curve == g.curve; });
          if (it == nears.end())
            nears.push_back({g.curve, dist, z, w});
          else if (dist < it->dist)
            *it = {g.curve, dist, z, w};
        }
      }
      double wsum = 0.0, zsum = 0.0, wmax = 0.0, carve = 0.0, cover = 0.0;
      double d0 = 1e300, d1 = 1e300, z0 = 0.0;  // nearest and second-nearest curve
      for (const Near& n : nears) {
        if (n.dist < d0) {
          d1 = d0;
          d0 = n.dist;
          z0 = n.z;
        } else if (n.dist < d1) {
          d1 = n.dist;
        }
        const double w = smoothstep01(1.0 - n.dist / radius);
        wsum += w;
        zsum += w * n.z;
        wmax = std::max(wmax, w);
        const double half = 0.5 * n.w;
        if (half > 0.0 && n.dist < half)
          carve = std::max(carve, p.depth_ratio * n.w * (1.0 - (n.dist / half) * (n.dist / half)));
        cover = std::max(cover, std::clamp((half - n.dist) / spacing + 0.5, 0.0, 1.0));
      }
      double h = h0;
      if (wsum > 0.0 && std::isfinite(h0)) {
        // SeamScape §2.2.4 with the ratio on the right side: the nearest curve's height on it, the weighted mean of
        // the curves within the radius where two curves are equally near.
        const double rho = d1 < 1e299 && d1 > 0.0 ? std::clamp(d0 / d1, 0.0, 1.0) : 0.0;
        const double river = (1.0 - rho) * z0 + rho * (zsum / wsum);
        h = h0 + std::clamp(p.strength, 0.0, 1.0) * wmax * (river - h0);
      }
      r.terrain->at(i, j) = static_cast<float>(h - carve);
      r.mask->at(i, j) = static_cast<float>(cover);
    }
  };
  for_each_row(ctx, d.height(), row);
  return r;
}

}  // namespace orogen::island
