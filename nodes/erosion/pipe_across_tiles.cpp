// PipeErosion across the tiles of a tiled or distributed build, exact (graph/tile_graph.h): each tile steps its own
// samples on a grid grown by a 2-sample halo taken from its neighbors' border bands every step.
//
// A step reads the fields within 2 samples (nodes/erosion/pipe_step.h), and its length is the CFL step of the deepest
// water over the whole domain after the step before: a maximum, exact in any order, but one every step, so every step
// is a round. Round 0 exchanges the bands of what does not change (the input heights, which say where the sinks are,
// and the linked fields), and in Drops mode each tile's bits of which samples take a second draw, for the tiles to
// their right (the drops of a row follow one stream of draws from the domain's first column). Round r >= 1 runs step
// r - 1 on every tile and exchanges the bands of the seven fields a step reads (terrain, water, sediment and the four
// outflow fluxes) with the tile's deepest water and its simulated time; every rank sees every message, so all step
// alike and stop together. The last round also gives the largest accumulated flow over all tiles, the `flow` map's
// scale.
//
// Why a halo of one step rather than k steps with a 2k-sample one: the step's length needs the reduction every step
// anyway, and 2k-sample bands every k steps carry the same bytes as 2-sample bands every step, while the grown grid
// repeats more work.
#include "nodes/erosion/pipe_across_tiles.h"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "graph/node_type.h"
#include "graph/tile_bytes.h"
#include "graph/tile_graph.h"
#include "nodes/common/finite_inputs.h"
#include "nodes/erosion/pipe_step.h"
#include "nodes/erosion/tile_bands.h"

namespace orogen::erosion {
namespace {

constexpr int kHalo = 2;          // a step reads the fields within 2 samples
constexpr int kStaticFields = 6;  // in, mask, rainfall_rate, moisture, evaporation_factor, hardness (input order)
constexpr int kStepFields = 7;    // PipeGrid::Terrain .. PipeGrid::FluxUp

// A message: the tile's rectangle, which static fields it sends (a bit per input, round 0) and how many channels,
// whether its Drops bits follow, then after a step its simulated time, its deepest water and (last step) its largest
// accumulated flow; then each channel's bands, then the Drops bits of its samples (64 a word, row after row).
struct Header {
  SampleRect rect;
  std::int32_t fields = 0, channels = 0, drop_bits = 0, last = 0;
  double time = 0.0, deepest = 0.0;
  float most = 0.0f;
  static constexpr std::size_t kBytes = 8 * sizeof(std::int32_t) + 2 * sizeof(double) + sizeof(float);
};

void put_header(std::string& out, const Header& h) {
  bytes::put(out, h.rect);
  for (const std::int32_t v : {h.fields, h.channels, h.drop_bits, h.last}) bytes::put(out, v);
  bytes::put(out, h.time), bytes::put(out, h.deepest), bytes::put(out, h.most);
}

Header take_header(std::string_view in) {
  const char* what = "pipe erosion bands";
  Header h;
  h.rect = bytes::take<SampleRect>(in, what);
  h.fields = bytes::take<std::int32_t>(in, what), h.channels = bytes::take<std::int32_t>(in, what);
  h.drop_bits = bytes::take<std::int32_t>(in, what), h.last = bytes::take<std::int32_t>(in, what);
  h.time = bytes::take<double>(in, what), h.deepest = bytes::take<double>(in, what);
  h.most = bytes::take<float>(in, what);
  return h;
}

std::size_t words_of(std::size_t bits) { return (bits + 63) / 64; }

class PipeTile : public TileGraphTile {
 public:
  PipeTile(std::vector<HeightfieldPtr> fields, const PipeParams& p, const Domain& whole)
      : fields_(std::move(fields)),
        p_(p),
        whole_domain_(whole),
        whole_(whole.resolution),
        rect_(rect_of(fields_[0]->domain, whole)) {
    grid_lo_ = glm::max(rect_.lo - kHalo, glm::ivec2(0));
    grid_size_ = glm::min(rect_.hi + kHalo, whole_ - 1) - grid_lo_ + 1;
  }

  std::string message(int round) override {
    Header h;
    h.rect = rect_;
    std::string out;
    if (round == 0) {
      std::vector<const Heightfield*> sent;
      for (int f = 0; f < kStaticFields; ++f)
        if (fields_[static_cast<std::size_t>(f)]) h.fields |= 1 << f, sent.push_back(fields_[f].get());
      h.channels = static_cast<std::int32_t>(sent.size());
      h.drop_bits = p_.rain_mode == RainMode::Drops;
      put_header(out, h);
      const Bands bands(rect_, whole_, kHalo);
      for (const Heightfield* f : sent)
        bands.for_each([&](glm::ivec2 s) { bytes::put(out, f->at(s.x - rect_.lo.x, s.y - rect_.lo.y)); });
      if (h.drop_bits) {
        const Heightfield& in = *fields_[0];
        const Heightfield* moisture = fields_[3].get();
        std::vector<std::uint64_t> bits(words_of(in.data.size()), 0);
        for (std::size_t k = 0; k < in.data.size(); ++k)
          if (pipe_drop_draws(p_, in.data[k], moisture ? moisture->data[k] : 1.0f)) bits[k >> 6] |= 1ull << (k & 63);
        for (const std::uint64_t w : bits) bytes::put(out, w);
      }
      return out;
    }
    // Step round - 1, its length from the deepest water over all tiles after the step before.
    const auto [dt, last] =
        pipe_step_length(p_, std::min(whole_domain_.spacing.x, whole_domain_.spacing.y), time_, deepest_);
    grid_->step(dt, static_cast<std::uint64_t>(round - 1), last);
    time_ += dt;
    h.time = time_;
    h.last = last;
    h.deepest = own_max(grid_->field(PipeGrid::Water));
    if (last) h.most = static_cast<float>(own_max(grid_->field(PipeGrid::Accumulated)));
    h.channels = last ? 0 : kStepFields;
    put_header(out, h);
    out.reserve(out.size() + static_cast<std::size_t>(h.channels) * cells_->bands.size() * sizeof(float));
    for (int c = 0; c < h.channels; ++c)
      cells_->bands.append(out, grid_->field(static_cast<PipeGrid::Field>(c)).data());
    return out;
  }

  void answer(int round, std::string_view in) override {
    const char* what = "pipe erosion halo";
    if (round == 0) {
      start_grid(in);
    } else {
      deepest_ = bytes::take<double>(in, what);
      most_ = bytes::take<float>(in, what);
      const auto channels = bytes::take<std::int32_t>(in, what);
      if (channels < 0 || channels > kStepFields ||
          in.size() < static_cast<std::size_t>(channels) * cells_->halo.size() * sizeof(float))
        throw std::invalid_argument("pipe erosion halo: truncated bytes");
      for (int c = 0; c < channels; ++c)
        cells_->halo.take(in, grid_->field(static_cast<PipeGrid::Field>(c)).data(), what);
    }
    if (!in.empty()) throw std::invalid_argument("pipe erosion halo: bytes left over");
  }

  std::vector<PortValue> outputs() override {
    const Heightfield& in = *fields_[0];
    PipeMaps maps;
    maps.out = std::make_shared<Heightfield>(in.domain);
    maps.water = std::make_shared<Heightfield>(in.domain);
    maps.velocity = std::make_shared<Heightfield>(in.domain);
    maps.flow = std::make_shared<Heightfield>(in.domain);
    const float area = grid_->cell_area();
    const double scale = pipe_flow_scale(most_, area);
    const auto& b = grid_->field(PipeGrid::Terrain);
    const auto& s = grid_->field(PipeGrid::Sediment);
    const auto& d = grid_->field(PipeGrid::Water);
    const auto& v = grid_->field(PipeGrid::Speed);
    const auto& acc = grid_->field(PipeGrid::Accumulated);
    for (int j = 0; j < in.height(); ++j)
      for (int i = 0; i < in.width(); ++i) {
        const std::size_t q = cell(rect_.lo + glm::ivec2(i, j)), k = in.index(i, j);
        maps.out->data[k] = b[q] + s[q];  // what is still suspended settles
        maps.water->data[k] = d[q];
        maps.velocity->data[k] = v[q];
        maps.flow->data[k] = pipe_flow(acc[q], scale, area);
      }
    fill_change_maps(in, maps, nullptr);
    return {HeightfieldPtr(maps.out),  HeightfieldPtr(maps.erosion), HeightfieldPtr(maps.deposition),
            HeightfieldPtr(maps.flow), HeightfieldPtr(maps.water),   HeightfieldPtr(maps.velocity)};
  }

 private:
  // The grid of the tile grown by the halo (within the domain) from round 0's answer: the static fields' halos, then
  // the Drops bits of the columns before the grid on its rows.
  void start_grid(std::string_view& in) {
    const char* what = "pipe erosion halo";
    const Domain grid_domain = whole_domain_.subdomain(grid_lo_.x, grid_lo_.y, grid_size_.x, grid_size_.y);
    for (int f = 0; f < kStaticFields; ++f) {
      const HeightfieldPtr& own = fields_[static_cast<std::size_t>(f)];
      if (!own) continue;
      auto g = std::make_shared<Heightfield>(grid_domain);
      for (int j = 0; j < own->height(); ++j)
        for (int i = 0; i < own->width(); ++i) g->data[cell(rect_.lo + glm::ivec2(i, j))] = own->at(i, j);
      grids_[static_cast<std::size_t>(f)] = g;
    }
    for (int f = 0; f < kStaticFields; ++f)
      if (grids_[static_cast<std::size_t>(f)])
        for_each_halo(rect_, whole_, kHalo, [&](glm::ivec2 s) {
          grids_[static_cast<std::size_t>(f)]->data[cell(s)] = bytes::take<float>(in, what);
        });
    cells_.emplace(rect_, whole_, kHalo, [&](glm::ivec2 s) { return cell(s); });
    PipeWindow window;
    window.first = grid_lo_;
    window.whole = whole_;
    if (p_.rain_mode == RainMode::Drops) {
      window.draws_before.resize(words_of(static_cast<std::size_t>(grid_lo_.x) * grid_size_.y));
      for (std::uint64_t& w : window.draws_before) w = bytes::take<std::uint64_t>(in, what);
    }
    // The tile's own fields are in the grids now.
    const auto g = [&](int f) { return grids_[static_cast<std::size_t>(f)].get(); };
    grid_ = std::make_unique<PipeGrid>(*g(0), p_, g(1), g(2), g(3), g(4), g(5), std::move(window));
    for (int f = 1; f < kStaticFields; ++f) fields_[static_cast<std::size_t>(f)].reset();
  }

  // The largest value of `f` on the tile's own samples.
  double own_max(const std::vector<float>& f) const {
    float m = 0.0f;
    for (int j = rect_.lo.y; j <= rect_.hi.y; ++j) {
      const float* row = f.data() + cell(glm::ivec2(rect_.lo.x, j));
      for (int i = 0; i <= rect_.hi.x - rect_.lo.x; ++i) m = std::max(m, row[i]);
    }
    return m;
  }

  std::size_t cell(glm::ivec2 s) const {
    return static_cast<std::size_t>(s.y - grid_lo_.y) * static_cast<std::size_t>(grid_size_.x) +
           static_cast<std::size_t>(s.x - grid_lo_.x);
  }

  std::vector<HeightfieldPtr> fields_;  // on the tile, in input order (the linked ones)
  std::vector<std::shared_ptr<Heightfield>> grids_ =
      std::vector<std::shared_ptr<Heightfield>>(kStaticFields);  // the same on the grid
  PipeParams p_;
  Domain whole_domain_;
  glm::ivec2 whole_;
  SampleRect rect_;
  glm::ivec2 grid_lo_, grid_size_;  // the grid: the tile grown by the halo, within the domain
  std::unique_ptr<PipeGrid> grid_;
  std::optional<BandCells> cells_;     // of the grid
  double time_ = 0.0, deepest_ = 0.0;  // simulated time, deepest water over all tiles after the last step
  float most_ = 0.0f;                  // largest accumulated flow over all tiles, after the last step
};

class PipeAcrossTiles : public TileGraphAlgorithm {
 public:
  PipeAcrossTiles(const PipeParams& p, const Domain& whole) : params_(p), whole_domain_(whole) {}

  int rounds() const override { return 1; }

  // Round r >= 1 ran step r - 1; the run ends at the step that reaches the duration, as the whole-domain run does.
  bool another_round(int round, const std::vector<std::string>& messages) const override {
    if (round == 0) return params_.duration > kPipeTimeSlack;
    return !take_headers(messages)[0].last;
  }

  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    std::vector<HeightfieldPtr> fields;
    for (std::size_t k = 0; k < kStaticFields; ++k) fields.push_back(tile_heightfield(inputs, k));
    if (!fields[0]) throw std::invalid_argument("pipe erosion across tiles needs a heightfield input");
    for (const auto& f : fields)
      if (f && f->domain.resolution != fields[0]->domain.resolution)
        throw std::invalid_argument("pipe erosion across tiles: every field must lie on the tile");
    require_finite_inputs("PipeErosion", {{"in", fields[0].get()},
                                          {"mask", fields[1].get()},
                                          {"rainfall_rate", fields[2].get()},
                                          {"moisture", fields[3].get()},
                                          {"evaporation_factor", fields[4].get()},
                                          {"hardness", fields[5].get()}});
    return std::make_unique<PipeTile>(std::move(fields), params_, whole_domain_);
  }

  // Round 0: each tile's static halos and the Drops bits before its grid. Then each tile's halos of the step's fields,
  // with the deepest water and largest accumulated flow over all tiles.
  std::vector<std::string> solve(int round, const std::vector<std::string>& messages) const override {
    const std::size_t count = messages.size();
    const auto headers = take_headers(messages);
    const glm::ivec2 whole = whole_domain_.resolution;
    std::vector<std::size_t> bands_bytes(count);
    std::vector<SampleRect> rects;
    for (const Header& h : headers) rects.push_back(h.rect);
    const auto halos = plans_.get(std::move(rects), whole, kHalo, "pipe erosion bands");
    std::vector<const char*> bands(count);
    for (std::size_t t = 0; t < count; ++t) {
      const Header& h = headers[t];
      if (h.channels != headers[0].channels || h.fields != headers[0].fields || h.last != headers[0].last ||
          h.time != headers[0].time || h.drop_bits != headers[0].drop_bits)
        throw std::invalid_argument("pipe erosion bands: the tiles' messages do not fit together");
      bands_bytes[t] = static_cast<std::size_t>(h.channels) * halos->stride[t];
      bands[t] = messages[t].data() + Header::kBytes;
      const glm::ivec2 size = h.rect.size();
      const std::size_t bits = h.drop_bits ? words_of(static_cast<std::size_t>(size.x) * size.y) * 8 : 0;
      if (messages[t].size() != Header::kBytes + bands_bytes[t] + bits)
        throw std::invalid_argument("pipe erosion bands: truncated bytes");
    }
    std::vector<std::string> answers(count);
    double deepest = 0.0;
    float most = 0.0f;
    for (const Header& h : headers) deepest = std::max(deepest, h.deepest), most = std::max(most, h.most);
    // The Drops bits of the whole domain, put together from the tiles (shared samples agree).
    std::vector<std::uint64_t> domain_bits;
    if (round == 0 && headers[0].drop_bits) {
      domain_bits.assign(words_of(static_cast<std::size_t>(whole.x) * whole.y), 0);
      for (std::size_t t = 0; t < count; ++t) {
        const SampleRect& r = headers[t].rect;
        const char* at = messages[t].data() + Header::kBytes + bands_bytes[t];
        const int w = r.size().x;
        for (int j = r.lo.y; j <= r.hi.y; ++j)
          for (int i = r.lo.x; i <= r.hi.x; ++i) {
            const std::size_t k = static_cast<std::size_t>(j - r.lo.y) * w + (i - r.lo.x);
            std::uint64_t word;
            std::memcpy(&word, at + (k >> 6) * 8, 8);
            if ((word >> (k & 63)) & 1u) {
              const std::size_t q = static_cast<std::size_t>(j) * whole.x + i;
              domain_bits[q >> 6] |= 1ull << (q & 63);
            }
          }
      }
    }
    for (std::size_t u = 0; u < count; ++u) {
      std::string& out = answers[u];
      if (round > 0) {
        bytes::put(out, deepest);
        bytes::put(out, most);
        bytes::put(out, headers[u].channels);
      }
      append_halo(out, *halos, u, headers[u].channels, bands);
      if (!domain_bits.empty()) {
        // The bits of columns 0 .. x0 - 1 on the rows of the tile's grid.
        const SampleRect& r = headers[u].rect;
        const int x0 = std::max(r.lo.x - kHalo, 0), y0 = std::max(r.lo.y - kHalo, 0),
                  y1 = std::min(r.hi.y + kHalo, whole.y - 1);
        std::vector<std::uint64_t> bits(words_of(static_cast<std::size_t>(x0) * (y1 - y0 + 1)), 0);
        for (int j = y0; j <= y1; ++j)
          for (int i = 0; i < x0; ++i) {
            const std::size_t q = static_cast<std::size_t>(j) * whole.x + i;
            if ((domain_bits[q >> 6] >> (q & 63)) & 1u) {
              const std::size_t b = static_cast<std::size_t>(j - y0) * x0 + i;
              bits[b >> 6] |= 1ull << (b & 63);
            }
          }
        for (const std::uint64_t w : bits) bytes::put(out, w);
      }
    }
    return answers;
  }

 private:
  std::vector<Header> take_headers(const std::vector<std::string>& messages) const {
    std::vector<Header> headers;
    const glm::ivec2 whole = whole_domain_.resolution;
    for (const auto& m : messages) {
      headers.push_back(take_header(m));
      check_tile_rect(headers.back().rect, whole, "pipe erosion bands");
    }
    if (headers.empty()) throw std::invalid_argument("pipe erosion bands: no tiles");
    return headers;
  }

  PipeParams params_;
  Domain whole_domain_;
  mutable HaloPlanCache plans_;
};

}  // namespace

std::unique_ptr<TileGraphAlgorithm> pipe_across_tiles(const PipeParams& p, const Domain& whole) {
  if (whole.resolution.x > 0 && whole.resolution.y > 0) check_pipe_work(p, whole);
  return std::make_unique<PipeAcrossTiles>(p, whole);
}

namespace {

// The node's parameters (erosion_nodes.cpp reads the same ones).
PipeParams pipe_params_of(const ParamView& v) {
  PipeParams p;
  p.duration = v.get<double>("duration");
  p.rain_rate = v.get<double>("rainfall_rate");
  p.rain_mode = v.get<std::string>("rain_mode") == "drops" ? RainMode::Drops : RainMode::Uniform;
  p.drop_chance = v.get<double>("drop_chance");
  p.capacity = v.get<double>("capacity");
  p.dissolving = v.get<double>("dissolving");
  p.depositing = v.get<double>("depositing");
  p.evaporation = v.get<double>("evaporation");
  p.gravity = v.get<double>("gravity");
  p.courant = v.get<double>("courant");
  p.layer_depth = v.get<double>("layer_depth");
  p.sea_level = v.get<double>("sea_level");
  p.seed = v.get<std::uint64_t>("seed");
  return p;
}

// Every parameter value and every linked input runs across the tiles; a run the whole-domain node would refuse (too
// much work) stays on the whole domain, whose node reports why (tile_graph_for).
const bool kPipeRegistered = register_tile_graph(
    "PipeErosion", [](const ParamView& v, const Domain& whole) { return pipe_across_tiles(pipe_params_of(v), whole); });

}  // namespace
}  // namespace orogen::erosion
