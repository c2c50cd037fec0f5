#include "nodes/field/normalize.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "graph/registry.h"
#include "graph/tile_bytes.h"
#include "graph/tile_graph.h"
#include "nodes/field/field_map.h"
#include "nodes/field/field_range.h"
#include "nodes/field/remap.h"

namespace orogen {

std::shared_ptr<Heightfield> normalize_field(const Heightfield& in, double lo, double hi, const ExecContext* ctx) {
  return normalize_field(in, field_range(in, ctx), lo, hi, ctx);
}

std::shared_ptr<Heightfield> normalize_field(const Heightfield& in, const ValueRange& range, double lo, double hi,
                                             const ExecContext* ctx) {
  if (range.empty || range.min == range.max)
    return map_field(
        in, [=](double h) { return std::isnan(h) ? h : lo; }, ctx);
  const RemapRange r{range.min, range.max, lo, hi, true};
  return map_field(
      in, [&](double h) { return std::isnan(h) ? h : remap_value(h, r); }, ctx);
}

OROGEN_NODE(Normalize) {
  b.distribution(Distribution::Reduction);
  b.reach_global();  // the range of the whole domain
  b.category("field").description(
      "Stretches a field linearly so that its lowest sample becomes `min` and its highest `max` (a height "
      "range in metres, or 0..1 for a mask). Depends on the whole domain: a tiled or distributed build combines "
      "the tiles' ranges into the whole domain's, so its tiles equal the untiled build (a single --tile alone "
      "computes the whole domain first).");
  b.input("in", PortType::Heightfield).description("Field to normalize");
  b.output("out", PortType::Heightfield).description("Field spanning exactly [min, max]");
  b.param_float("min", 0.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Value of the lowest sample, in the input's units");
  b.param_float("max", 1.0)
      .unit(Unit::InputUnits)
      .range(-1e6, 1e6)
      .soft_range(-1000, 1000)
      .description("Value of the highest sample, in the input's units");
  b.execute([](ExecContext& ctx) {
    const auto in = ctx.require<Heightfield>("in");
    ctx.set_output("out", normalize_field(*in, ctx.param<double>("min"), ctx.param<double>("max"), &ctx));
  });
}

namespace {

// Across the tiles of a tiled or distributed build (graph/tile_graph.h): each tile sends its range, the whole
// domain's range is their union (min and max are exact, in any order), and each tile normalizes with it.
class NormalizeTile : public TileGraphTile {
 public:
  NormalizeTile(HeightfieldPtr in, double lo, double hi) : in_(std::move(in)), lo_(lo), hi_(hi) {}
  std::string message(int) override {
    const ValueRange r = field_range(*in_);
    std::string out;
    bytes::put(out, r.min), bytes::put(out, r.max), bytes::put(out, static_cast<std::uint8_t>(r.empty));
    return out;
  }
  void answer(int, std::string_view in) override { range_ = take_range(in); }
  std::vector<PortValue> outputs() override { return {HeightfieldPtr(normalize_field(*in_, range_, lo_, hi_))}; }

  static ValueRange take_range(std::string_view in) {
    ValueRange r;
    r.min = bytes::take<double>(in, "field range"), r.max = bytes::take<double>(in, "field range");
    r.empty = bytes::take<std::uint8_t>(in, "field range") != 0;
    if (!in.empty()) throw std::invalid_argument("field range: trailing bytes");
    return r;
  }

 private:
  HeightfieldPtr in_;
  double lo_, hi_;
  ValueRange range_;
};

class NormalizeAcrossTiles : public TileGraphAlgorithm {
 public:
  NormalizeAcrossTiles(double lo, double hi) : lo_(lo), hi_(hi) {}
  int rounds() const override { return 1; }
  std::unique_ptr<TileGraphTile> start(const std::vector<PortValue>& inputs) const override {
    const auto* in = inputs.empty() ? nullptr : std::get_if<HeightfieldPtr>(&inputs[0]);
    if (!in || !*in) throw std::invalid_argument("Normalize across tiles needs a heightfield input");
    return std::make_unique<NormalizeTile>(*in, lo_, hi_);
  }
  std::vector<std::string> solve(int, const std::vector<std::string>& messages) const override {
    ValueRange whole;
    for (const auto& m : messages) {
      const ValueRange r = NormalizeTile::take_range(m);
      if (r.empty) continue;
      whole.min = whole.empty ? r.min : std::min(whole.min, r.min);
      whole.max = whole.empty ? r.max : std::max(whole.max, r.max);
      whole.empty = false;
    }
    std::string answer;
    bytes::put(answer, whole.min), bytes::put(answer, whole.max),
        bytes::put(answer, static_cast<std::uint8_t>(whole.empty));
    return std::vector<std::string>(messages.size(), answer);
  }

 private:
  double lo_, hi_;
};

const bool kNormalizeAcrossTiles =
    register_tile_graph("Normalize", [](const ParamView& p, const Domain&) -> std::unique_ptr<TileGraphAlgorithm> {
      return std::make_unique<NormalizeAcrossTiles>(p.get<double>("min"), p.get<double>("max"));
    });

}  // namespace

}  // namespace orogen
