#include "nodes/climate/kmeans.h"

#include <cstring>
#include <stdexcept>

#include <algorithm>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "graph/heightfield.h"
#include "graph/registry.h"
#include "graph/report.h"
#include "graph/tile_bytes.h"
#include "nodes/climate/kmeans_steps.h"
#include "nodes/common/categorical_palette.h"
#include "nodes/common/hash.h"
#include "nodes/common/report_builder.h"

namespace orogen::climate {
namespace {

constexpr std::size_t kBlock = kmeans_block;  // cells per task and per fast exact sum

// Nearest centre of `count` cells (features x, uc per cell) among k centres transposed to ct[channel][kp]:
// float squared distances summed channel by channel; ties go to the lower id. Every variant below performs
// the same IEEE operations in the same order for each cell (no FMA), so the result does not depend on the
// variant or the machine. KP > 0: the padded cluster count is known at compile time and four cells are
// processed together (independent accumulators in registers).
template <int KP>
inline __attribute__((always_inline)) void nearest_impl(const float* x, std::size_t count, std::size_t uc,
                                                        const float* ct, std::size_t kp_runtime, int k,
                                                        std::int32_t* best_out, float* dist_out) {
  const std::size_t kp = KP > 0 ? static_cast<std::size_t>(KP) : kp_runtime;
  auto finish = [&](const float* d, std::size_t q) {
    int best = 0;
    float bd = d[0];
    for (int c = 1; c < k; ++c)
      if (d[c] < bd) {
        bd = d[c];
        best = c;
      }
    best_out[q] = best;
    dist_out[q] = bd;
  };
  std::size_t q = 0;
  if constexpr (KP > 0) {
    // Four lanes of clusters per vector, P cells at once; every lane does the scalar operations.
    typedef float V __attribute__((vector_size(16)));
    constexpr int NV = KP / 4;
    constexpr int P = KP <= 8 ? 4 : 2;
    for (; q + P <= count; q += P) {
      V acc[P][NV];
      for (int p = 0; p < P; ++p)
        for (int t = 0; t < NV; ++t) acc[p][t] = V{0.0f, 0.0f, 0.0f, 0.0f};
      const float* x0 = x + q * uc;
      for (std::size_t ch = 0; ch < uc; ++ch) {
        V cv[NV];
        for (int t = 0; t < NV; ++t) __builtin_memcpy(&cv[t], ct + ch * KP + 4 * t, sizeof(V));
        for (int p = 0; p < P; ++p) {
          const float xv = x0[static_cast<std::size_t>(p) * uc + ch];
          const V xb = {xv, xv, xv, xv};
          for (int t = 0; t < NV; ++t) {
            const V e = xb - cv[t];
            acc[p][t] += e * e;
          }
        }
      }
      for (int p = 0; p < P; ++p) {
        float d[KP];
        for (int t = 0; t < NV; ++t) __builtin_memcpy(d + 4 * t, &acc[p][t], sizeof(V));
        finish(d, q + static_cast<std::size_t>(p));
      }
    }
  }
  float d[64 + 4];
  for (; q < count; ++q) {
    const float* xq = x + q * uc;
    for (std::size_t c = 0; c < kp; ++c) d[c] = 0.0f;
    for (std::size_t ch = 0; ch < uc; ++ch) {
      const float xv = xq[ch];
      const float* cc = ct + ch * kp;
      for (std::size_t c = 0; c < kp; ++c) {
        const float e = xv - cc[c];
        d[c] += e * e;
      }
    }
    finish(d, q);
  }
}

#define OROGEN_NEAREST(NAME, KP)                                                                                 \
  __attribute__((target_clones("avx2", "default"))) void NAME(const float* x, std::size_t count, std::size_t uc, \
                                                              const float* ct, std::size_t kp, int k,            \
                                                              std::int32_t* best, float* dist) {                 \
    nearest_impl<KP>(x, count, uc, ct, kp, k, best, dist);                                                       \
  }
OROGEN_NEAREST(nearest_any, 0)
OROGEN_NEAREST(nearest_4, 4)
OROGEN_NEAREST(nearest_8, 8)
OROGEN_NEAREST(nearest_12, 12)
OROGEN_NEAREST(nearest_16, 16)
#undef OROGEN_NEAREST

void nearest_centres(const float* x, std::size_t count, std::size_t uc, const float* ct, std::size_t kp, int k,
                     std::int32_t* best, float* dist) {
  switch (kp) {
    case 4:
      nearest_4(x, count, uc, ct, kp, k, best, dist);
      break;
    case 8:
      nearest_8(x, count, uc, ct, kp, k, best, dist);
      break;
    case 12:
      nearest_12(x, count, uc, ct, kp, k, best, dist);
      break;
    case 16:
      nearest_16(x, count, uc, ct, kp, k, best, dist);
      break;
    default:
      nearest_any(x, count, uc, ct, kp, k, best, dist);
  }
}

}  // namespace

std::vector<double> group_weights(const std::vector<std::string>& names, int channels, double slope, double temperature,
                                  double illumination, double humidity, double other) {
  std::vector<double> w(static_cast<std::size_t>(channels), other);
  for (std::size_t c = 0; c < w.size() && c < names.size(); ++c) {
    const std::string& n = names[c];
    auto starts = [&](const char* p) { return n.rfind(p, 0) == 0; };
    if (n == "slope")
      w[c] = slope;
    else if (starts("temperature"))
      w[c] = temperature;
    else if (starts("illumination"))
      w[c] = illumination;
    else if (starts("humidity"))
      w[c] = humidity;
  }
  return w;
}

KMeansFeatures kmeans_features(const Image& features, const std::vector<double>& weights, glm::ivec2 counted,
                               const ExecContext* ctx) {
  KMeansFeatures f;
  f.width = features.width(), f.height = features.height(), f.channels = features.channels;
  const std::size_t n = features.domain.sample_count(), uc = static_cast<std::size_t>(features.channels);
  const std::size_t W = static_cast<std::size_t>(f.width);
  const std::size_t cw = static_cast<std::size_t>(std::max(0, counted.x)),
                    chh = static_cast<std::size_t>(std::max(0, counted.y));
  f.sw.assign(uc, 1.0);
  for (std::size_t c = 0; c < uc && c < weights.size(); ++c) f.sw[c] = std::sqrt(std::max(0.0, weights[c]));
  f.x.resize(n * uc);
  // A cell with a NaN or infinite feature belongs to no cluster (label -1, NaN in the output): it is left out
  // of every assignment, sum and count (NaN propagates; it never becomes a cluster id).
  f.valid.assign(n, 1);
  f.tallied.assign(n, 0);
  // Block by block, each block's floors right after its features (still in cache).
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  f.fast_floor.assign(blocks * uc, 0.0f);
  f.below_floor.assign(blocks * uc, 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    if (ctx) ctx->check_cancelled();
    std::vector<float> hi(uc);  // per channel: the largest magnitude (NaN left out)
    for (std::size_t b = r.begin(); b != r.end(); ++b) {
      const std::size_t q0 = b * kBlock, q1 = std::min(n, (b + 1) * kBlock);
      for (std::size_t q = q0; q < q1; ++q) {
        for (std::size_t c = 0; c < uc; ++c) {
          const float v = features.data[q * uc + c];
          f.x[q * uc + c] = std::isfinite(v) ? static_cast<float>(v * f.sw[c]) : 0.0f;
          if (!std::isfinite(v)) f.valid[q] = 0;
        }
        f.tallied[q] = f.valid[q] && q % W < cw && q / W < chh;  // else another tile's sample
      }
      std::fill(hi.begin(), hi.end(), 0.0f);
      for (std::size_t q = q0; q < q1; ++q) {
        if (!f.tallied[q]) continue;
        const float* xq = f.x.data() + q * uc;
        for (std::size_t c = 0; c < uc; ++c) hi[c] = std::max(hi[c], std::abs(xq[c]));
      }
      float* const floor = f.fast_floor.data() + b * uc;
      std::uint8_t* const below = f.below_floor.data() + b * uc;
      for (std::size_t c = 0; c < uc; ++c) floor[c] = exact_double_floor(hi[c], kmeans_block_bits);
      for (std::size_t q = q0; q < q1; ++q) {
        if (!f.tallied[q]) continue;
        const float* xq = f.x.data() + q * uc;
        for (std::size_t c = 0; c < uc; ++c) below[c] |= !(std::abs(xq[c]) >= floor[c]) && xq[c] != 0.0f;
      }
    }
  });
  return f;
}

KMeansTally::KMeansTally(int k, int channels)
    : counts(static_cast<std::size_t>(k), 0), sums(static_cast<std::size_t>(k) * static_cast<std::size_t>(channels)) {}

void KMeansTally::add(const KMeansTally& o) {
  for (std::size_t c = 0; c < counts.size(); ++c) counts[c] += o.counts[c];
  changed += o.changed;
  objective.add(o.objective);
  for (std::size_t e = 0; e < sums.size(); ++e) sums[e].add(o.sums[e]);
  if (raw.empty()) raw.resize(o.raw.size());
  if (raw.size() != o.raw.size()) throw std::invalid_argument("k-means tally: different zero-weight channels");
  for (std::size_t e = 0; e < raw.size(); ++e) raw[e].add(o.raw[e]);
}

void KMeansTally::put(std::string& out) const {
  bytes::put(out, changed);
  for (std::int64_t c : counts) bytes::put(out, c);
  objective.put(out);
  for (const auto& s : sums) s.put(out);
  bytes::put(out, static_cast<std::uint64_t>(raw.size()));
  for (const auto& s : raw) s.put(out);
}

KMeansTally KMeansTally::take(std::string_view& in, int k, int channels) {
  constexpr const char* what = "k-means tally";
  KMeansTally t(k, channels);
  t.changed = bytes::take<std::int64_t>(in, what);
  for (auto& c : t.counts) c = bytes::take<std::int64_t>(in, what);
  bool ok = t.objective.take(in);
  for (auto& s : t.sums) ok = ok && s.take(in);
  if (!ok) throw std::invalid_argument("k-means tally: truncated");
  const auto raw = bytes::take<std::uint64_t>(in, what);
  if (raw > t.sums.size() || raw % t.counts.size() != 0)
    throw std::invalid_argument("k-means tally: a bad number of raw sums");
  t.raw.resize(static_cast<std::size_t>(raw));
  for (auto& s : t.raw)
    if (!s.take(in)) throw std::invalid_argument("k-means tally: truncated");
  return t;
}

KMeansTally kmeans_assign(const KMeansFeatures& f, const std::vector<double>& centres, int k,
                          std::vector<std::int32_t>& labels, const ExecContext* ctx) {
  const std::size_t n = f.valid.size(), uc = static_cast<std::size_t>(f.channels), uk = static_cast<std::size_t>(k);
  // Distances in float, vectorised across clusters: centres transposed to [channel][cluster], padded to 4.
  const std::size_t kp = (uk + 3) & ~std::size_t{3};
  std::vector<float> ct(uc * kp, 0.0f);
  for (std::size_t c = 0; c < uk; ++c)
    for (std::size_t ch = 0; ch < uc; ++ch) ct[ch * kp + c] = static_cast<float>(centres[c * uc + ch]);
  // Each thread tallies the blocks it gets; the exact sums make the total independent of how the blocks fall. Within
  // a block the values of a channel at or above its floor (KMeansFeatures::fast_floor) add up exactly in a double; the
  // few below go to buckets of doubles (exact for up to FloatBuckets::kMaxAdds cells), moved into the clusters' exact
  // sums before they could take more and at the end. The distances likewise, with a floor per block.
  static_assert(kBlock <= static_cast<std::size_t>(FloatBuckets::kMaxAdds));
  struct Local {
    KMeansTally tally;
    std::vector<double> fast;        // k x channels, this block's sums at or above the floor
    std::vector<FloatBuckets> rest;  // channels x k: the values below the floor
    std::vector<char> touched;       // per channel: values in `rest` since they were last moved
    FloatBuckets objective;          // the distances below the floor
    std::size_t pending = 0;         // cells since then
    void move(std::size_t uc, std::size_t uk) {
      objective.move_into(tally.objective);
      for (std::size_t ch = 0; ch < uc; ++ch) {
        if (!touched[ch]) continue;
        touched[ch] = 0;
        for (std::size_t c = 0; c < uk; ++c) rest[ch * uk + c].move_into(tally.sums[c * uc + ch]);
      }
      pending = 0;
    }
  };
  tbb::enumerable_thread_specific<Local> locals([&] {
    return Local{KMeansTally(k, f.channels),
                 std::vector<double>(uk * uc, 0.0),
                 std::vector<FloatBuckets>(uc * uk),
                 std::vector<char>(uc, 0),
                 FloatBuckets{},
                 0};
  });
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    if (ctx) ctx->check_cancelled();
    Local& local = locals.local();
    KMeansTally& t = local.tally;
    std::int32_t best_of[kBlock];
    float dist_of[kBlock];
    std::int64_t members[64];
    for (std::size_t b = r.begin(); b != r.end(); ++b) {
      const std::size_t q0 = b * kBlock, q1 = std::min(n, (b + 1) * kBlock), m = q1 - q0;
      if (local.pending + m > static_cast<std::size_t>(FloatBuckets::kMaxAdds)) local.move(uc, uk);
      local.pending += m;
      const float* const floor = f.fast_floor.data() + b * uc;
      const std::uint8_t* const below = f.below_floor.data() + b * uc;
      const std::uint8_t* const tallied = f.tallied.data() + q0;
      std::fill(members, members + uk, 0);
      nearest_centres(f.x.data() + q0 * uc, m, uc, ct.data(), kp, k, best_of, dist_of);
      float hi = 0.0f;  // the largest distance (NaN left out)
      for (std::size_t e = 0; e < m; ++e) hi = std::max(hi, dist_of[e]);
      const float objective_floor = exact_double_floor(hi, kmeans_block_bits);
      double objective = 0.0;
      for (std::size_t e = 0; e < m; ++e) {
        if (!f.valid[q0 + e]) continue;  // label stays -1
        const int best = best_of[e];
        const bool changed = labels[q0 + e] != best;
        labels[q0 + e] = best;
        if (!tallied[e]) continue;
        t.changed += changed;
        const float d = dist_of[e];
        if (d >= objective_floor)
          objective += d;
        else
          local.objective.add(d);
        ++members[best];
      }
      // The sums at or above the floors, in a loop of their own (tight: the compiler vectorizes across the channels);
      // a value below its floor adds 0 there.
      double* const fast = local.fast.data();
      const float* const x = f.x.data() + q0 * uc;
      const bool any_below = std::any_of(below, below + uc, [](std::uint8_t v) { return v != 0; });
      if (!any_below) {
        for (std::size_t e = 0; e < m; ++e) {
          if (!tallied[e]) continue;
          double* d = fast + static_cast<std::size_t>(best_of[e]) * uc;
          const float* xq = x + e * uc;
          for (std::size_t ch = 0; ch < uc; ++ch) d[ch] += xq[ch];
        }
      } else {
        for (std::size_t e = 0; e < m; ++e) {
          if (!tallied[e]) continue;
          double* d = fast + static_cast<std::size_t>(best_of[e]) * uc;
          const float* xq = x + e * uc;
          for (std::size_t ch = 0; ch < uc; ++ch) d[ch] += std::abs(xq[ch]) >= floor[ch] ? xq[ch] : 0.0f;
        }
        // The values below the floors, channel by channel (a channel's k buckets stay in cache).
        for (std::size_t ch = 0; ch < uc; ++ch) {
          if (!below[ch]) continue;
          local.touched[ch] = 1;
          FloatBuckets* const rest = local.rest.data() + ch * uk;
          for (std::size_t e = 0; e < m; ++e) {
            const float v = x[e * uc + ch];
            if (tallied[e] && !(std::abs(v) >= floor[ch])) rest[best_of[e]].add(v);
          }
        }
      }
      t.objective.add_exact(objective);
      for (std::size_t c = 0; c < uk; ++c) {
        if (!members[c]) continue;
        t.counts[c] += members[c];
        double* d = fast + c * uc;
        for (std::size_t ch = 0; ch < uc; ++ch) {
          t.sums[c * uc + ch].add_exact(d[ch]);
          d[ch] = 0.0;
        }
      }
    }
  });
  for (Local& l : locals) l.move(uc, uk);
  KMeansTally total(k, f.channels);
  for (const Local& l : locals) total.add(l.tally);
  return total;
}

std::vector<ExactFloatSum> kmeans_raw_sums(const KMeansFeatures& f, const Image& raw,
                                           const std::vector<std::int32_t>& labels, int k, const ExecContext* ctx) {
  const std::size_t uc = static_cast<std::size_t>(f.channels), uk = static_cast<std::size_t>(k);
  std::vector<std::size_t> zero;  // the zero-weight channels
  for (std::size_t ch = 0; ch < uc; ++ch)
    if (!(f.sw[ch] > 0.0)) zero.push_back(ch);
  if (zero.empty()) return {};
  const std::size_t nz = zero.size(), n = f.tallied.size();
  tbb::enumerable_thread_specific<std::vector<ExactFloatSum>> locals(uk * nz);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kBlock), [&](const tbb::blocked_range<std::size_t>& r) {
    if (ctx) ctx->check_cancelled();
    ExactFloatSum* const sums = locals.local().data();
    for (std::size_t q = r.begin(); q != r.end(); ++q) {
      if (!f.tallied[q]) continue;
      ExactFloatSum* s = sums + static_cast<std::size_t>(labels[q]) * nz;
      for (std::size_t i = 0; i < nz; ++i) s[i].add(raw.data[q * uc + zero[i]]);  // finite: the cell is valid
    }
  });
  std::vector<ExactFloatSum> total(uk * nz);
  for (const auto& l : locals)
    for (std::size_t e = 0; e < total.size(); ++e) total[e].add(l[e]);
  return total;
}

void kmeans_update(const KMeansTally& t, int k, int channels, std::vector<double>& centres) {
  const std::size_t uc = static_cast<std::size_t>(channels);
  for (std::size_t c = 0; c < static_cast<std::size_t>(k); ++c)
    if (t.counts[c] > 0)
      for (std::size_t ch = 0; ch < uc; ++ch)
        centres[c * uc + ch] = t.sums[c * uc + ch].value() / static_cast<double>(t.counts[c]);
}

std::vector<double> kmeans_raw_means(const std::vector<ExactFloatSum>& raw, const std::vector<std::int64_t>& counts) {
  std::vector<double> m(raw.size(), 0.0);
  const std::size_t per_cluster = counts.empty() ? 0 : raw.size() / counts.size();
  for (std::size_t c = 0; c < counts.size(); ++c)
    if (counts[c] > 0)
      for (std::size_t i = 0; i < per_cluster; ++i)
        m[c * per_cluster + i] = raw[c * per_cluster + i].value() / static_cast<double>(counts[c]);
  return m;
}

void kmeans_finish(const std::vector<std::int64_t>& counts, const std::vector<double>& centres,
                   const std::vector<double>& raw_means, const std::vector<double>& sw, KMeansResult& r) {
  const std::size_t uc = sw.size(), uk = counts.size();
  const std::size_t zero =
      static_cast<std::size_t>(std::count_if(sw.begin(), sw.end(), [](double w) { return !(w > 0.0); }));
  if (raw_means.size() != uk * zero) throw std::invalid_argument("k-means: raw means of other channels");
  r.counts = counts;
  r.centres.resize(uk * uc);
  // With a zero weight a channel's centre is the plain mean of its members.
  for (std::size_t c = 0; c < uk; ++c)
    for (std::size_t ch = 0, i = 0; ch < uc; ++ch)
      r.centres[c * uc + ch] = sw[ch] > 0.0 ? centres[c * uc + ch] / sw[ch] : raw_means[c * zero + i++];
}

glm::ivec2 kmeans_diagonal_cell(int c, int k, int width, int height) {
  const double t = (c + 0.5) / k;
  return {static_cast<int>(std::lround(t * (width - 1))), static_cast<int>(std::lround(t * (height - 1)))};
}

KMeansResult kmeans(const Image& features, const KMeansParams& p, const ExecContext* ctx) {
  const int C = features.channels;
  const std::size_t n = features.domain.sample_count();
  if (C < 1) throw NodeError("k-means: the image has no channels");
  if (p.k < 1 || p.k > 64) throw NodeError("k-means: k must be in 1..64");
  if (p.max_iterations < 1) throw NodeError("k-means: max_iterations must be at least 1");
  const int k = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(p.k), n));
  const std::size_t uc = static_cast<std::size_t>(C), uk = static_cast<std::size_t>(k);
  const int W = features.width(), H = features.height();
  const KMeansFeatures f = kmeans_features(features, p.weights, {W, H}, ctx);
  const std::vector<float>& x = f.x;
  const std::vector<char>& valid = f.valid;
  auto dist2 = [&](std::size_t q, const double* centre) {
    double d = 0.0;
    const float* xq = x.data() + q * uc;
    for (std::size_t c = 0; c < uc; ++c) {
      const double e = xq[c] - centre[c];
      d += e * e;
    }
    return d;
  };

  // Initial centres (scaled units).
  std::vector<double> centres(uk * uc);
  auto set_centre = [&](int c, std::size_t q) {
    for (std::size_t ch = 0; ch < uc; ++ch) centres[static_cast<std::size_t>(c) * uc + ch] = x[q * uc + ch];
  };
  if (p.init == KMeansInit::Diagonal) {
    for (int c = 0; c < k; ++c) {
      const glm::ivec2 cell = kmeans_diagonal_cell(c, k, W, H);
      set_centre(
          c, n ? static_cast<std::size_t>(cell.y) * static_cast<std::size_t>(W) + static_cast<std::size_t>(cell.x) : 0);
    }
  } else {
    set_centre(0, static_cast<std::size_t>(hash64(p.seed, 0) % n));
    std::vector<double> d2(n, std::numeric_limits<double>::infinity());
    for (int c = 1; c < k; ++c) {
      const double* prev = centres.data() + static_cast<std::size_t>(c - 1) * uc;
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kBlock), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t q = r.begin(); q != r.end(); ++q) d2[q] = valid[q] ? std::min(d2[q], dist2(q, prev)) : 0.0;
      });
      double total = 0.0;
      for (double v : d2) total += v;
      std::size_t pick = static_cast<std::size_t>(hash64(p.seed, static_cast<std::uint64_t>(c)) % n);
      if (total > 0.0 && std::isfinite(total)) {
        const double target = hash01(p.seed ^ 0x5DEECE66Dull, static_cast<std::uint64_t>(c)) * total;
        double run = 0.0;
        for (std::size_t q = 0; q < n; ++q) {
          run += d2[q];
          if (run > target && d2[q] > 0.0) {
            pick = q;
            break;
          }
        }
      }
      set_centre(c, pick);
      if (ctx) ctx->check_cancelled();
    }
  }

  KMeansResult res;
  res.k = k;
  res.channels = C;
  res.labels.assign(n, -1);
  KMeansTally last(k, C);
  for (int it = 0; it < p.max_iterations; ++it) {
    last = kmeans_assign(f, centres, k, res.labels, ctx);
    res.objective.push_back(last.objective.value());
    res.iterations = it + 1;
    if (kmeans_converged(last.changed, p.tolerance, n)) {
      res.converged = true;
      break;
    }
    kmeans_update(last, k, C, centres);
    if (ctx) ctx->progress(static_cast<double>(it + 1) / p.max_iterations);
  }
  kmeans_finish(last.counts, centres, kmeans_raw_means(kmeans_raw_sums(f, features, res.labels, k, ctx), last.counts),
                f.sw, res);
  return res;
}

KMeansMaps kmeans_maps(const KMeansResult& r, const Domain& domain) {
  KMeansMaps m{std::make_shared<Heightfield>(domain), std::make_shared<Image>(domain, 4)};
  m.color->channel_names = {"R", "G", "B", "A"};
  m.color->color = true;
  for (std::size_t q = 0; q < r.labels.size(); ++q) {
    if (r.labels[q] < 0) {  // a cell with a non-finite feature: NaN id, transparent colour
      m.ids->data[q] = std::numeric_limits<float>::quiet_NaN();
      for (int ch = 0; ch < 4; ++ch) m.color->data[q * 4 + static_cast<std::size_t>(ch)] = 0.0f;
      continue;
    }
    m.ids->data[q] = static_cast<float>(r.labels[q]);
    const glm::vec4 c = categorical_linear(r.labels[q]);
    for (int ch = 0; ch < 4; ++ch) m.color->data[q * 4 + static_cast<std::size_t>(ch)] = c[ch];
  }
  return m;
}

std::string kmeans_report(const KMeansResult& r, const std::vector<std::string>& channel_names) {
  ReportJson j;
  j["k"] = r.k;
  j["iterations"] = r.iterations;
  j["converged"] = r.converged;
  j["objective"] = ReportJson::array();
  for (double o : r.objective) j["objective"].push_back(report_number(o));
  j["clusters"] = ReportJson::array();
  for (int c = 0; c < r.k; ++c) {
    ReportJson cl;
    cl["id"] = c;
    cl["count"] = r.counts[static_cast<std::size_t>(c)];
    const glm::vec4 col = categorical_linear(c);
    cl["color"] = {col.r, col.g, col.b};
    ReportJson center = ReportJson::object();
    for (int ch = 0; ch < r.channels; ++ch) {
      const std::string name = static_cast<std::size_t>(ch) < channel_names.size()
                                   ? channel_names[static_cast<std::size_t>(ch)]
                                   : "channel_" + std::to_string(ch);
      center[name] = report_number(r.centres[static_cast<std::size_t>(c * r.channels + ch)]);
    }
    cl["center"] = center;
    j["clusters"].push_back(cl);
  }
  return report_text(j);
}

OROGEN_NODE(KMeansClusters) {
  b.distribution(Distribution::Reduction);
  b.reach_global();
  b.category("climate").description(
      "Clusters the cells of a multi-channel image (a ResourceStack) into k groups by k-means (S. P. Lloyd "
      "(1982), Least squares quantization in PCM) on a weighted squared distance sum_c w_c (a_c - b_c)^2, "
      "the ecosystems of H. Long (2016), Using procedural methods to generate realistic virtual rural worlds "
      "(chapter 4; his weights: slope, temperature and illumination 1, soil humidity 0.1). Initial centers "
      "at equal steps along the terrain diagonal (Long) or by k-means++ from the seed (D. Arthur, S. "
      "Vassilvitskii (2007), k-means++: the advantages of careful seeding). Iterates until at most tolerance x the "
      "cells change cluster (0: none) or max_iterations. The new centers are exact sums of the members' features "
      "rounded once, so the result is bit-identical for any thread count, and a tiled or distributed build with "
      "init diagonal runs it across the tiles (each tile sums its cells; one small all-gather per iteration) with "
      "the untiled build's labels; k-means++ computes on the whole domain.");
  b.input("in", PortType::Image).description("Features per cell (ResourceStack.out or any image)");
  b.output("out", PortType::Heightfield)
      .description("Cluster id 0..k-1 (NaN where a feature is NaN or infinite)")
      .kind(OutputKind::Scalar);
  b.output("report", PortType::Report)
      .description("Centers (per channel, feature units), member counts, colors, objective per iteration");
  b.output("color", PortType::Image)
      .description("Cluster colors from a categorical palette, linear RGBA (transparent where the id is NaN)");
  b.param_int("k", 6).unit(Unit::Count).range(1, 64).description("Number of clusters, 1..64");
  b.param_int("max_iterations", 100).unit(Unit::Count).range(1, 1000).description("Iteration cap, 1..1000");
  b.param_float("tolerance", 1e-4)
      .unit(Unit::Unitless)
      .range(0.0, 0.5)
      .description(
          "Stop when at most this fraction of the cells changed cluster in an iteration, 0..0.5 (0: until none "
          "changes)");
  b.param_enum("init", {"diagonal", "kmeans++"}, "diagonal")
      .description(
          "Initial centers: diagonal (cells at equal steps along the domain diagonal) or kmeans++ (from the seed)");
  b.param_seed("seed", 0).description("Seed of the kmeans++ initialization");
  b.param_float("weight_slope", 1.0)
      .unit(Unit::Unitless)
      .range(0.0, 1000.0)
      .description("Weight of the 'slope' channel, unitless >= 0");
  b.param_float("weight_temperature", 1.0)
      .unit(Unit::Unitless)
      .range(0.0, 1000.0)
      .description("Weight of 'temperature_*' channels, unitless >= 0");
  b.param_float("weight_illumination", 1.0)
      .unit(Unit::Unitless)
      .range(0.0, 1000.0)
      .description("Weight of 'illumination_*' channels, unitless >= 0");
  b.param_float("weight_humidity", 0.1)
      .unit(Unit::Unitless)
      .range(0.0, 1000.0)
      .description("Weight of 'humidity_*' channels, unitless >= 0");
  b.param_float("weight_other", 1.0)
      .unit(Unit::Unitless)
      .range(0.0, 1000.0)
      .description("Weight of any other channel, unitless >= 0");
  b.execute([](ExecContext& ctx) {
    const auto img = ctx.require<Image>("in");
    KMeansParams p;
    p.k = static_cast<int>(ctx.param<std::int64_t>("k"));
    p.max_iterations = static_cast<int>(ctx.param<std::int64_t>("max_iterations"));
    p.tolerance = ctx.param<double>("tolerance");
    p.init = ctx.param<std::string>("init") == "kmeans++" ? KMeansInit::PlusPlus : KMeansInit::Diagonal;
    p.seed = ctx.param<std::uint64_t>("seed");
    p.weights = group_weights(img->channel_names, img->channels, ctx.param<double>("weight_slope"),
                              ctx.param<double>("weight_temperature"), ctx.param<double>("weight_illumination"),
                              ctx.param<double>("weight_humidity"), ctx.param<double>("weight_other"));
    const KMeansResult r = kmeans(*img, p, &ctx);
    const KMeansMaps maps = kmeans_maps(r, img->domain);
    ctx.set_output("out", maps.ids);
    ctx.set_output("report", make_report(kmeans_report(r, img->channel_names)));
    ctx.set_output("color", maps.color);
  });
}

}  // namespace orogen::climate
