#include "nodes/climate/kmeans.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "graph/heightfield.h"
#include "graph/registry.h"
#include "graph/report.h"
#include "nodes/common/categorical_palette.h"
#include "nodes/common/hash.h"
#include "nodes/common/report_builder.h"

namespace orogen::climate {
namespace {

constexpr std::size_t kBlock = 4096;  // cells per partial sum (fixed: results do not depend on threads)

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

KMeansResult kmeans(const Image& features, const KMeansParams& p, const ExecContext* ctx) {
  const int C = features.channels;
  const std::size_t n = features.domain.sample_count();
  if (C < 1) throw NodeError("k-means: the image has no channels");
  if (p.k < 1 || p.k > 64) throw NodeError("k-means: k must be in 1..64");
  if (p.max_iterations < 1) throw NodeError("k-means: max_iterations must be at least 1");
  const int k = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(p.k), n));
  const std::size_t uc = static_cast<std::size_t>(C), uk = static_cast<std::size_t>(k);
  // Features scaled by sqrt(weight): plain squared distance afterwards.
  std::vector<double> sw(uc, 1.0);
  for (std::size_t c = 0; c < uc && c < p.weights.size(); ++c) sw[c] = std::sqrt(std::max(0.0, p.weights[c]));
  std::vector<float> x(n * uc);
  // A cell with a NaN or infinite feature belongs to no cluster (label -1, NaN in the output): it is left out
  // of every assignment, sum and count (NaN propagates; it never becomes a cluster id).
  std::vector<char> valid(n, 1);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kBlock), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t q = r.begin(); q != r.end(); ++q)
      for (std::size_t c = 0; c < uc; ++c) {
        const float v = features.data[q * uc + c];
        x[q * uc + c] = std::isfinite(v) ? static_cast<float>(v * sw[c]) : 0.0f;
        if (!std::isfinite(v)) valid[q] = 0;
      }
  });
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
  const int W = features.width(), H = features.height();
  if (p.init == KMeansInit::Diagonal) {
    for (int c = 0; c < k; ++c) {
      const double t = (c + 0.5) / k;
      const int i = static_cast<int>(std::lround(t * (W - 1))), j = static_cast<int>(std::lround(t * (H - 1)));
      set_centre(c, features.domain.sample_count()
                        ? static_cast<std::size_t>(j) * static_cast<std::size_t>(W) + static_cast<std::size_t>(i)
                        : 0);
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
  const std::size_t blocks = (n + kBlock - 1) / kBlock;
  std::vector<double> block_sums(blocks * uk * uc), block_obj(blocks);
  std::vector<std::int64_t> block_counts(blocks * uk), block_changed(blocks);
  std::vector<std::int64_t> counts(uk);
  // Distances in float, vectorised across clusters: centres transposed to [channel][cluster], padded to 4.
  const std::size_t kp = (uk + 3) & ~std::size_t{3};
  std::vector<float> ct(uc * kp, 0.0f);
  for (int it = 0; it < p.max_iterations; ++it) {
    for (std::size_t c = 0; c < uk; ++c)
      for (std::size_t ch = 0; ch < uc; ++ch) ct[ch * kp + c] = static_cast<float>(centres[c * uc + ch]);
    // Assignment and per-block sums.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
      if (ctx) ctx->check_cancelled();
      std::int32_t best_of[kBlock];
      float dist_of[kBlock];
      for (std::size_t b = r.begin(); b != r.end(); ++b) {
        double* sums = block_sums.data() + b * uk * uc;
        std::int64_t* cnt = block_counts.data() + b * uk;
        std::fill(sums, sums + uk * uc, 0.0);
        std::fill(cnt, cnt + uk, 0);
        double obj = 0.0;
        std::int64_t changed = 0;
        const std::size_t q0 = b * kBlock, q1 = std::min(n, (b + 1) * kBlock);
        nearest_centres(x.data() + q0 * uc, q1 - q0, uc, ct.data(), kp, k, best_of, dist_of);
        for (std::size_t q = q0; q < q1; ++q) {
          if (!valid[q]) continue;  // label stays -1
          const int best = best_of[q - q0];
          changed += res.labels[q] != best;
          res.labels[q] = best;
          obj += dist_of[q - q0];
          ++cnt[best];
          double* s = sums + static_cast<std::size_t>(best) * uc;
          const float* xq = x.data() + q * uc;
          for (std::size_t ch = 0; ch < uc; ++ch) s[ch] += xq[ch];
        }
        block_obj[b] = obj;
        block_changed[b] = changed;
      }
    });
    // Fixed-order reduction.
    double obj = 0.0;
    std::int64_t changed = 0;
    std::vector<double> sums(uk * uc, 0.0);
    std::fill(counts.begin(), counts.end(), 0);
    for (std::size_t b = 0; b < blocks; ++b) {
      obj += block_obj[b];
      changed += block_changed[b];
      for (std::size_t c = 0; c < uk; ++c) counts[c] += block_counts[b * uk + c];
      const double* s = block_sums.data() + b * uk * uc;
      for (std::size_t e = 0; e < uk * uc; ++e) sums[e] += s[e];
    }
    res.objective.push_back(obj);
    res.iterations = it + 1;
    if (static_cast<double>(changed) <= p.tolerance * static_cast<double>(n)) {
      res.converged = true;
      break;
    }
    for (std::size_t c = 0; c < uk; ++c)
      if (counts[c] > 0)
        for (std::size_t ch = 0; ch < uc; ++ch)
          centres[c * uc + ch] = sums[c * uc + ch] / static_cast<double>(counts[c]);
    if (ctx) ctx->progress(static_cast<double>(it + 1) / p.max_iterations);
  }
  res.counts = counts;
  res.centres.resize(uk * uc);
  for (std::size_t c = 0; c < uk; ++c)
    for (std::size_t ch = 0; ch < uc; ++ch)
      res.centres[c * uc + ch] = sw[ch] > 0.0 ? centres[c * uc + ch] / sw[ch] : 0.0;
  // With a zero weight a channel's centre is the plain mean of its members.
  for (std::size_t ch = 0; ch < uc; ++ch) {
    if (sw[ch] > 0.0) continue;
    std::vector<double> s(uk, 0.0);
    for (std::size_t q = 0; q < n; ++q) {
      if (res.labels[q] < 0) continue;
      const float v = features.data[q * uc + ch];
      s[static_cast<std::size_t>(res.labels[q])] += std::isfinite(v) ? v : 0.0;
    }
    for (std::size_t c = 0; c < uk; ++c)
      res.centres[c * uc + ch] = counts[c] ? s[c] / static_cast<double>(counts[c]) : 0.0;
  }
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
      "cells change cluster (0: none) or max_iterations. Bit-identical for any thread count.");
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
