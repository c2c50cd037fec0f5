#include "nodes/climate/kmeans_across_tiles.h"

#include <algorithm>
#include <stdexcept>

#include "graph/registry.h"
#include "graph/tile_bytes.h"
#include "nodes/climate/kmeans_steps.h"
#include "nodes/common/report_builder.h"

namespace orogen::climate {
namespace {

// Round 0: each tile sends the features of the initial centres' cells it owns; the solve puts the centres together.
// Round r >= 1 (iteration r): each tile assigns its cells to the centres it holds and sends them with its tally;
// the solve adds the tallies, decides whether the iterations end and gives every tile the new centres (and, at the
// end, the counts and the means of the zero-weight channels). A tile owns the samples it holds but for the last
// column and row it shares with the tiles after it (tiles share their border samples, cli/tiling.h).

// k x channels centres; throws std::invalid_argument naming `what` on bytes that do not hold them.
std::vector<double> take_centres(std::string_view& in, std::size_t count, const char* what) {
  auto v = bytes::take_vector<double>(in, what);
  if (v.size() != count) throw std::invalid_argument(std::string(what) + ": a bad number of centres");
  return v;
}

class KMeansTile : public TileGraphTile {
 public:
  KMeansTile(ImagePtr image, const KMeansGroupWeights& g, const Domain& whole, int k)
      : image_(std::move(image)), k_(k) {
    const Image& img = *image_;
    if (img.channels < 1) throw NodeError("k-means: the image has no channels");
    const glm::ivec2 at = img.domain.first - whole.first, size = img.domain.resolution;
    counted_ = {at.x + size.x == whole.resolution.x ? size.x : size.x - 1,
                at.y + size.y == whole.resolution.y ? size.y : size.y - 1};
    at_ = at;
    whole_size_ = whole.resolution;
    features_ = kmeans_features(
        img,
        group_weights(img.channel_names, img.channels, g.slope, g.temperature, g.illumination, g.humidity, g.other),
        counted_);
    labels_.assign(img.domain.sample_count(), -1);
  }

  std::string message(int round) override {
    std::string out;
    bytes::put(out, static_cast<std::int32_t>(features_.channels));
    const std::size_t uc = static_cast<std::size_t>(features_.channels);
    if (round == 0) {
      for (int c = 0; c < k_; ++c) {
        const glm::ivec2 cell = kmeans_diagonal_cell(c, k_, whole_size_.x, whole_size_.y) - at_;
        if (cell.x < 0 || cell.y < 0 || cell.x >= counted_.x || cell.y >= counted_.y) continue;
        bytes::put(out, static_cast<std::int32_t>(c));
        const std::size_t q = static_cast<std::size_t>(cell.y) * static_cast<std::size_t>(features_.width) +
                              static_cast<std::size_t>(cell.x);
        const float* x = features_.x.data() + q * uc;
        bytes::put_vector(out, std::vector<float>(x, x + uc));
      }
      return out;
    }
    // The tally first: its bytes begin with `changed`, all that another_round reads. The raw sums go every round (a
    // tile does not know which round is the last); the solve uses the last round's.
    KMeansTally tally = kmeans_assign(features_, centres_, k_, labels_);
    tally.raw = kmeans_raw_sums(features_, *image_, labels_, k_);
    tally.put(out);
    bytes::put_vector(out, centres_);
    return out;
  }

  void answer(int round, std::string_view in) override {
    const std::size_t cells = static_cast<std::size_t>(k_) * static_cast<std::size_t>(features_.channels);
    if (round == 0) {
      centres_ = take_centres(in, cells, "k-means centres");
      return;
    }
    const auto done = bytes::take<std::uint8_t>(in, "k-means verdict");
    converged_ = bytes::take<std::uint8_t>(in, "k-means verdict") != 0;
    objective_.push_back(bytes::take<double>(in, "k-means verdict"));
    iterations_ = round;
    centres_ = take_centres(in, cells, "k-means verdict");
    if (done) {
      counts_.resize(static_cast<std::size_t>(k_));
      for (auto& c : counts_) c = bytes::take<std::int64_t>(in, "k-means verdict");
      raw_means_ = bytes::take_vector<double>(in, "k-means verdict");
    }
  }

  std::vector<PortValue> outputs() override {
    KMeansResult r;
    r.k = k_;
    r.channels = features_.channels;
    r.labels = std::move(labels_);
    r.objective = objective_;
    r.iterations = iterations_;
    r.converged = converged_;
    kmeans_finish(counts_, centres_, raw_means_, features_.sw, r);
    const KMeansMaps maps = kmeans_maps(r, image_->domain);
    return {HeightfieldPtr(maps.ids), ReportPtr(make_report(kmeans_report(r, image_->channel_names))),
            ImagePtr(maps.color)};
  }

 private:
  ImagePtr image_;
  int k_;
  KMeansFeatures features_;
  std::vector<std::int32_t> labels_;
  glm::ivec2 counted_{0, 0}, at_{0, 0}, whole_size_{0, 0};
  std::vector<double> centres_, raw_means_, objective_;
  std::vector<std::int64_t> counts_;
  int iterations_ = 0;
  bool converged_ = false;
};

class KMeansAcrossTiles : public TileGraphAlgorithm {
 public:
  KMeansAcrossTiles(const KMeansParams& p, const KMeansGroupWeights& g, const Domain& whole)
      : p_(p),
        g_(g),
        whole_(whole),
        k_(static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(p.k), whole.sample_count()))) {}

  int rounds() const override { return 2; }

  bool another_round(int round, const std::vector<std::string>& messages) const override {
    if (round == 0) return true;
    std::int64_t changed = 0;
    for (const auto& m : messages) {
      std::string_view in(m);
      bytes::take<std::int32_t>(in, "k-means tally");  // the channel count
      changed += bytes::take<std::int64_t>(in, "k-means tally");
    }
    return !finished(round, changed);
  }

  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    const auto* in = inputs.empty() ? nullptr : std::get_if<ImagePtr>(&inputs[0]);
    if (!in || !*in) throw std::invalid_argument("KMeansClusters across tiles needs an image input");
    return std::make_unique<KMeansTile>(*in, g_, whole_, k_);
  }

  std::vector<std::string> solve(int round, const std::vector<std::string>& messages) const override {
    if (messages.empty()) throw std::invalid_argument("k-means across tiles: no tiles");
    const int channels = channels_of(messages[0]);
    const std::size_t uc = static_cast<std::size_t>(channels), uk = static_cast<std::size_t>(k_);
    std::string answer;
    if (round == 0) {
      std::vector<double> centres(uk * uc);
      std::vector<int> found(uk, 0);
      for (const auto& m : messages) {
        std::string_view in(m);
        if (bytes::take<std::int32_t>(in, "k-means centres") != channels)
          throw std::invalid_argument("k-means across tiles: tiles with different channel counts");
        while (!in.empty()) {
          const auto c = bytes::take<std::int32_t>(in, "k-means centres");
          const auto x = bytes::take_vector<float>(in, "k-means centres");
          if (c < 0 || c >= k_ || x.size() != uc)
            throw std::invalid_argument("k-means across tiles: a bad initial centre");
          std::copy(x.begin(), x.end(),
                    centres.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(c) * uc));
          ++found[static_cast<std::size_t>(c)];
        }
      }
      if (std::any_of(found.begin(), found.end(), [](int f) { return f != 1; }))
        throw std::invalid_argument("k-means across tiles: an initial centre's cell owned by no tile or by two");
      bytes::put_vector(answer, centres);
      return std::vector<std::string>(messages.size(), answer);
    }
    KMeansTally total(k_, channels);
    std::vector<double> centres;
    for (std::size_t t = 0; t < messages.size(); ++t) {
      std::string_view in(messages[t]);
      if (bytes::take<std::int32_t>(in, "k-means tally") != channels)
        throw std::invalid_argument("k-means across tiles: tiles with different channel counts");
      total.add(KMeansTally::take(in, k_, channels));
      auto held = take_centres(in, uk * uc, "k-means tally");
      if (t == 0) centres = std::move(held);
      if (!in.empty()) throw std::invalid_argument("k-means tally: trailing bytes");
    }
    const bool converged = kmeans_converged(total.changed, p_.tolerance, whole_.sample_count());
    const bool done = finished(round, total.changed);
    if (!converged) kmeans_update(total, k_, channels, centres);
    bytes::put(answer, static_cast<std::uint8_t>(done));
    bytes::put(answer, static_cast<std::uint8_t>(converged));
    bytes::put(answer, total.objective.value());
    bytes::put_vector(answer, centres);
    if (done) {
      for (std::int64_t c : total.counts) bytes::put(answer, c);
      bytes::put_vector(answer, kmeans_raw_means(total.raw, total.counts));
    }
    return std::vector<std::string>(messages.size(), answer);
  }

 private:
  static int channels_of(const std::string& m) {
    std::string_view in(m);
    const auto c = bytes::take<std::int32_t>(in, "k-means message");
    if (c < 1) throw std::invalid_argument("k-means across tiles: an image without channels");
    return c;
  }
  // Whether round `round`'s assignment, in which `changed` cells changed cluster, ends the iterations.
  bool finished(int round, std::int64_t changed) const {
    return kmeans_converged(changed, p_.tolerance, whole_.sample_count()) || round >= p_.max_iterations;
  }

  KMeansParams p_;
  KMeansGroupWeights g_;
  Domain whole_;
  int k_;
};

const bool kKMeansAcrossTiles = register_tile_graph(
    "KMeansClusters",
    [](const ParamView& v, const Domain& whole) -> std::unique_ptr<TileGraphAlgorithm> {
      if (v.get<std::string>("init") != "diagonal") return nullptr;
      KMeansParams p;
      p.k = static_cast<int>(v.get<std::int64_t>("k"));
      p.max_iterations = static_cast<int>(v.get<std::int64_t>("max_iterations"));
      p.tolerance = v.get<double>("tolerance");
      KMeansGroupWeights g{v.get<double>("weight_slope"), v.get<double>("weight_temperature"),
                           v.get<double>("weight_illumination"), v.get<double>("weight_humidity"),
                           v.get<double>("weight_other")};
      return kmeans_across_tiles(p, g, whole);
    },
    "with init 'diagonal' (k-means++ picks its centers by a running sum over the whole domain in row order)");

}  // namespace

std::unique_ptr<TileGraphAlgorithm> kmeans_across_tiles(const KMeansParams& p, const KMeansGroupWeights& group,
                                                        const Domain& whole) {
  if (p.k < 1 || p.k > 64) throw NodeError("k-means: k must be in 1..64");
  if (p.max_iterations < 1) throw NodeError("k-means: max_iterations must be at least 1");
  return std::make_unique<KMeansAcrossTiles>(p, group, whole);
}

}  // namespace orogen::climate
