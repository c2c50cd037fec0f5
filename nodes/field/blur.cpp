#include "nodes/field/blur.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "graph/registry.h"
#include "nodes/field/row_loop.h"

namespace orogen {
namespace {

constexpr int kBoxPasses = 5;

// Index of the sample that stands in for position i of a line of n samples.
int edge_index(long i, int n, BlurEdges edges) {
  if (edges == BlurEdges::Clamp) return static_cast<int>(std::clamp<long>(i, 0, n - 1));
  const long period = 2L * n;
  long m = i % period;
  if (m < 0) m += period;
  return static_cast<int>(m < n ? m : period - 1 - m);
}

// The line extended by `pad` samples on both sides according to the edge rule.
void extend(const float* in, int n, int pad, BlurEdges edges, std::vector<double>& ext) {
  ext.resize(static_cast<std::size_t>(n + 2 * pad));
  for (int k = 0; k < n + 2 * pad; ++k) ext[static_cast<std::size_t>(k)] = in[edge_index(k - pad, n, edges)];
}

void blur_line_direct(const float* in, float* out, int n, double sigma, BlurEdges edges) {
  const int radius = std::max(1, static_cast<int>(std::ceil(4.0 * sigma)));
  std::vector<double> w(static_cast<std::size_t>(radius) + 1);
  double total = 0.0;
  for (int k = 0; k <= radius; ++k) {
    w[static_cast<std::size_t>(k)] = std::exp(-0.5 * k * k / (sigma * sigma));
    total += (k == 0 ? 1.0 : 2.0) * w[static_cast<std::size_t>(k)];
  }
  for (auto& v : w) v /= total;
  std::vector<double> ext;
  extend(in, n, radius, edges, ext);
  for (int i = 0; i < n; ++i) {
    const double* c = ext.data() + i + radius;
    double s = w[0] * c[0];
    for (int k = 1; k <= radius; ++k) s += w[static_cast<std::size_t>(k)] * (c[k] + c[-k]);
    out[i] = static_cast<float>(s);
  }
}

// Radius r and end weight alpha of an extended box with variance `var` (Gwosdek et al. 2011, Eq. 9-10).
struct ExtendedBox {
  int r = 0;
  double alpha = 0.0;
};
ExtendedBox extended_box(double var) {
  ExtendedBox b;
  b.r = static_cast<int>(std::floor((std::sqrt(1.0 + 12.0 * var) - 1.0) / 2.0));
  const double r = b.r;
  b.alpha = (2 * r + 1) * (var - r * (r + 1) / 3.0) / (2.0 * ((r + 1) * (r + 1) - var));
  return b;
}

void blur_line_boxes(const float* in, float* out, int n, double sigma, BlurEdges edges) {
  const ExtendedBox box = extended_box(sigma * sigma / kBoxPasses);
  const int reach = box.r + 1;
  const int pad = kBoxPasses * reach;
  std::vector<double> a, b, prefix;
  extend(in, n, pad, edges, a);
  // Each pass filters the samples that still have `reach` valid neighbours; after all passes exactly the
  // n samples of the line remain valid. Filtering the once-extended line is the same as extending the
  // input by the edge rule and convolving with the whole kernel.
  const double norm = 1.0 / (2 * box.r + 1 + 2 * box.alpha);
  int lo = 0, hi = n + 2 * pad;  // valid range [lo, hi) in `a`
  for (int pass = 0; pass < kBoxPasses; ++pass) {
    prefix.assign(a.size() + 1, 0.0);
    for (std::size_t k = 0; k < a.size(); ++k) prefix[k + 1] = prefix[k] + a[k];
    b.assign(a.size(), 0.0);
    for (int k = lo + reach; k < hi - reach; ++k) {
      const auto u = static_cast<std::size_t>(k);
      const double inner = prefix[u + box.r + 1] - prefix[u - box.r];
      b[u] = (inner + box.alpha * (a[u - reach] + a[u + reach])) * norm;
    }
    lo += reach;
    hi -= reach;
    std::swap(a, b);
  }
  for (int i = 0; i < n; ++i) out[i] = static_cast<float>(a[static_cast<std::size_t>(i + pad)]);
}

}  // namespace

void gaussian_blur_line(const float* in, float* out, int n, double sigma, BlurEdges edges) {
  if (n <= 0) return;
  if (!(sigma > 1e-3) || n == 1) {
    std::copy(in, in + n, out);
  } else if (sigma <= kDirectMaxSigma) {
    blur_line_direct(in, out, n, sigma, edges);
  } else {
    blur_line_boxes(in, out, n, sigma, edges);
  }
}

Heightfield gaussian_blur(const Heightfield& in, const BlurParams& p, const ExecContext* ctx) {
  const int w = in.width(), h = in.height();
  const double sx = p.sigma / in.domain.spacing.x, sy = p.sigma / in.domain.spacing.y;
  Heightfield tmp(in.domain), out(in.domain);
  for_each_row(ctx, h, [&](int j) { gaussian_blur_line(&in.row(j)[0], &tmp.row(j)[0], w, sx, p.edges); }, 0.0, 0.5);
  // Columns in blocks of adjacent ones, so each gathered row segment is one cache line.
  constexpr int kBlock = 16;
  const int blocks = (w + kBlock - 1) / kBlock;
  for_each_row(ctx, blocks, [&](int blk) {
    const int i0 = blk * kBlock, i1 = std::min(w, i0 + kBlock);
    std::vector<float> col(static_cast<std::size_t>(h) * kBlock), res(static_cast<std::size_t>(h));
    for (int j = 0; j < h; ++j)
      for (int i = i0; i < i1; ++i) col[static_cast<std::size_t>(i - i0) * h + j] = tmp.at(i, j);
    for (int i = i0; i < i1; ++i) {
      gaussian_blur_line(&col[static_cast<std::size_t>(i - i0) * h], res.data(), h, sy, p.edges);
      for (int j = 0; j < h; ++j) out.at(i, j) = res[static_cast<std::size_t>(j)];
    }
  }, 0.5, 1.0);
  return out;
}

OROGEN_NODE(Blur) {
  b.category("field").description(
      "Gaussian blur with its standard deviation in metres (separable; exact sampled Gaussian up to 12 samples "
      "of sigma, five extended-box passes with the exact variance beyond). Edges: clamp repeats the edge "
      "sample, mirror reflects the field and preserves its mean exactly.");
  b.input("in", PortType::Heightfield).description("Field to blur");
  b.output("out", PortType::Heightfield).description("Blurred field");
  b.param_float("sigma", 10.0).range(0.0, 1e5).soft_range(0.0, 500.0).unit("m")
      .description("Standard deviation of the Gaussian (the visible blur radius is about 2-3 sigma)");
  b.param_enum("edges", {"clamp", "mirror"}, "clamp").description("What lies beyond the domain's edges");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    const BlurParams p{ctx.param<double>("sigma"), static_cast<BlurEdges>(ctx.enum_index("edges"))};
    ctx.set_output("out", std::make_shared<Heightfield>(gaussian_blur(*in, p, &ctx)));
  });
}

}  // namespace orogen
