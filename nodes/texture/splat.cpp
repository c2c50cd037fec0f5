#include "nodes/texture/splat.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "graph/registry.h"
#include "nodes/common/match_domain.h"
#include "nodes/common/text.h"
#include "nodes/field/curvature.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/field/slope.h"
#include "nodes/field/surface_derivatives.h"

namespace orogen::texture {
namespace {

double number(const std::string& s, const std::string& where) {
  const std::string t = trim(s);
  char* end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (t.empty() || *end != '\0' || !std::isfinite(v)) throw NodeError(where + "'" + t + "' is not a finite number");
  return v;
}

}  // namespace

std::string default_splat_layers() {
  return "grass: slope < 30 ~ 8, height > 6 ~ 3, height < 1800 ~ 150\n"
         "dirt: weight = 0.15, slope < 42 ~ 8\n"
         "rock: slope > 36 ~ 8\n"
         "snow: height > 2000 ~ 150, slope < 50 ~ 8\n"
         "sand: height < 5 ~ 3, slope < 15 ~ 5\n";
}

std::vector<SplatLayer> parse_splat_layers(const std::string& text) {
  std::vector<SplatLayer> layers;
  std::istringstream in(text);
  std::string line;
  int number_of_line = 0;
  while (std::getline(in, line)) {
    ++number_of_line;
    if (trim(line).empty()) continue;
    const std::string where = "layer line " + std::to_string(number_of_line) + ": ";
    const auto colon = line.find(':');
    if (colon == std::string::npos) throw NodeError(where + "expected 'name: term, term, ...'");
    SplatLayer layer;
    layer.name = trim(line.substr(0, colon));
    if (layer.name.empty()) throw NodeError(where + "empty layer name");
    std::stringstream rest(line.substr(colon + 1));
    std::string term;
    while (std::getline(rest, term, ',')) {
      term = trim(term);
      if (term.empty()) continue;
      if (const auto eq = term.find('='); eq != std::string::npos) {
        if (trim(term.substr(0, eq)) != "weight") throw NodeError(where + "'" + term + "': only 'weight = w' takes '='");
        layer.weight = number(term.substr(eq + 1), where);
        if (layer.weight < 0.0) throw NodeError(where + "weight must be >= 0");
        continue;
      }
      const auto op = term.find_first_of("<>");
      if (op == std::string::npos) throw NodeError(where + "'" + term + "': expected 'input < t' or 'input > t'");
      SplatTerm t;
      const std::string input = trim(term.substr(0, op));
      if (input == "height") t.input = SplatInput::Height;
      else if (input == "slope") t.input = SplatInput::Slope;
      else if (input == "curvature") t.input = SplatInput::Curvature;
      else if (input == "flow") t.input = SplatInput::Flow;
      else if (input == "wetness") t.input = SplatInput::Wetness;
      else if (input == "field") t.input = SplatInput::Field;
      else throw NodeError(where + "unknown input '" + input + "' (height, slope, curvature, flow, wetness, field)");
      t.greater = term[op] == '>';
      std::string value = term.substr(op + 1);
      if (const auto tilde = value.find('~'); tilde != std::string::npos) {
        t.softness = number(value.substr(tilde + 1), where);
        if (t.softness < 0.0) throw NodeError(where + "softness must be >= 0");
        value = value.substr(0, tilde);
      }
      t.threshold = number(value, where);
      layer.terms.push_back(t);
    }
    layers.push_back(layer);
  }
  if (layers.empty()) throw NodeError("no layers");
  if (layers.size() > static_cast<std::size_t>(kMaxSplatLayers))
    throw NodeError("at most " + std::to_string(kMaxSplatLayers) + " layers, got " + std::to_string(layers.size()));
  return layers;
}

double splat_term(const SplatTerm& t, double x) {
  if (!std::isfinite(x)) return 0.0;
  double up;
  if (t.softness > 0.0) {
    const double s = std::clamp((x - (t.threshold - t.softness)) / (2.0 * t.softness), 0.0, 1.0);
    up = s * s * (3.0 - 2.0 * s);
  } else {
    up = x >= t.threshold ? 1.0 : 0.0;
  }
  return t.greater ? up : 1.0 - up;
}

SplatResult splat_weights(const SplatInputs& in, const std::vector<SplatLayer>& layers, const ExecContext* ctx) {
  const Heightfield& z = *in.height;
  bool need[6] = {};
  for (const auto& l : layers)
    for (const auto& t : l.terms) need[static_cast<int>(t.input)] = true;
  auto check = [&](SplatInput which, const Heightfield* f, const char* port) {
    if (!need[static_cast<int>(which)]) return;
    if (!f) throw NodeError(std::string("a rule uses '") + port + "' but that input is not connected");
    require_same_grid(f->domain, z.domain, port);
  };
  check(SplatInput::Flow, in.flow, "flow");
  check(SplatInput::Wetness, in.wetness, "wetness");
  check(SplatInput::Field, in.field, "field");
  const int n = static_cast<int>(layers.size());
  SplatResult out;
  out.weights = std::make_shared<Image>(z.domain, n);
  for (const auto& l : layers) out.weights->channel_names.push_back(l.name);
  out.dominant = std::make_shared<Heightfield>(z.domain);
  for (int k = 0; k < 2; ++k) {
    out.splat[k] = std::make_shared<Image>(z.domain, 4);
    out.splat[k]->channel_names = {"R", "G", "B", "A"};
  }
  const bool grid = z.width() > 1 || z.height() > 1;
  for_each_row(ctx, z.height(), [&](int j) {
    for (int i = 0; i < z.width(); ++i) {
      double v[6] = {z.at(i, j), 0.0, 0.0, 0.0, 0.0, 0.0};
      if (grid && (need[1] || need[2])) {
        const SurfaceDerivatives d = derivatives_at(z, i, j);
        v[1] = slope_degrees(d.p, d.q);
        v[2] = curvature_value(d, CurvatureKind::Mean);
      }
      if (in.flow && need[3]) v[3] = in.flow->at(i, j);
      if (in.wetness && need[4]) v[4] = in.wetness->at(i, j);
      if (in.field && need[5]) v[5] = in.field->at(i, j);
      double w[kMaxSplatLayers] = {};
      double sum = 0.0;
      for (int l = 0; l < n; ++l) {
        double x = layers[static_cast<std::size_t>(l)].weight;
        for (const auto& t : layers[static_cast<std::size_t>(l)].terms) x *= splat_term(t, v[static_cast<int>(t.input)]);
        w[l] = x;
        sum += x;
      }
      if (!(sum > 0.0) || !std::isfinite(sum)) {
        std::fill(w, w + n, 0.0);
        w[0] = sum = 1.0;
      }
      float* px = out.weights->pixel(i, j);
      int best = 0;
      for (int l = 0; l < n; ++l) {
        px[l] = static_cast<float>(w[l] / sum);
        if (px[l] > px[best]) best = l;
        out.splat[l / 4]->pixel(i, j)[l % 4] = px[l];
      }
      out.dominant->at(i, j) = static_cast<float>(best);
    }
  });
  return out;
}

OROGEN_NODE(SplatWeights) {
  b.reach_local(0.0, 1);  // slope and curvature from the 3 x 3 stencil
  b.category("texture").description(
      "Material weights per cell for up to 8 layers from rules on height (m), slope (degrees), mean "
      "curvature (1/m), flow, wetness or any field, with smoothstep edges; weights >= 0 summing to 1, the "
      "dominant layer, and RGBA splat maps (4 layers per image) for game engines. After the height and "
      "steepness rules of L. Potter (2017), Generating a Virtual Forest Environment using Procedural Content "
      "Generation. Layers, one per line: 'name: term, term, ...' with terms 'input < t ~ s', 'input > t ~ s' "
      "(soft over [t - s, t + s]; s = 0 is a hard step) and 'weight = w'; inputs height, slope, curvature, "
      "flow, wetness, field. Raw weight = w x product of the terms, then normalized; where all are 0 the "
      "first layer takes the cell. Height bands (H. Zaiz (2022), Procedural Generation of 3D Game Worlds) "
      "are layers with height terms and softness 0.");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.input("flow", PortType::Heightfield).optional().description("Flow for 'flow' rules (e.g. FlowAccumulation.flow, 0..1)");
  b.input("wetness", PortType::Heightfield).optional().description("Wetness for 'wetness' rules (e.g. FlowAccumulation.wetness)");
  b.input("field", PortType::Heightfield).optional().description("Any field for 'field' rules");
  b.output("out", PortType::Image).description("Weights, one channel per layer (named by the layer), summing to 1");
  b.output("dominant", PortType::Heightfield).description("Id of the heaviest layer (0-based, in layer order)").kind(OutputKind::Scalar);
  b.output("splat0", PortType::Image).description("Layers 0..3 as RGBA");
  b.output("splat1", PortType::Image).description("Layers 4..7 as RGBA (0 where absent)");
  b.param_string("layers", default_splat_layers()).description("One layer per line: 'name: input < t ~ s, input > t ~ s, weight = w' (heights in m, slopes in degrees)");
  b.execute([](ExecContext& ctx) {
    const auto layers = parse_splat_layers(ctx.param<std::string>("layers"));
    const auto z = ctx.require<Heightfield>("in");
    const auto flow = secondary_input<Heightfield>(ctx, "flow", z->domain);
    const auto wet = secondary_input<Heightfield>(ctx, "wetness", z->domain);
    const auto field = secondary_input<Heightfield>(ctx, "field", z->domain);
    auto r = splat_weights({z.get(), flow.get(), wet.get(), field.get()}, layers, &ctx);
    ctx.set_output("out", r.weights);
    ctx.set_output("dominant", r.dominant);
    ctx.set_output("splat0", r.splat[0]);
    ctx.set_output("splat1", r.splat[1]);
  });
}

}  // namespace orogen::texture
