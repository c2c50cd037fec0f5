#include "nodes/texture/splat.h"

#include <algorithm>
#include <cmath>

#include "graph/registry.h"
#include "graph/table_json.h"
#include "nodes/common/match_domain.h"
#include "nodes/field/curvature.h"
#include "nodes/common/cancellable_rows.h"
#include "nodes/common/smoothstep.h"
#include "nodes/field/slope.h"
#include "nodes/field/surface_derivatives.h"

namespace orogen::texture {
TableSchema splat_layer_schema() {
  TableSchema s;
  s.min_rows = 1;
  s.max_rows = kMaxSplatLayers;
  s.add("name", ColumnType::Text).describe("Layer name: the weight channel's name");
  s.add("weight", ColumnType::Number)
      .range(0.0, 1e9)
      .unit_of(Unit::Unitless)
      .describe("Raw weight before the rules multiply it, >= 0");
  return s;
}

TableSchema splat_rule_schema() {
  TableSchema s;
  s.add("layer", ColumnType::Text).describe("The layer (a name in `layers`) this rule multiplies");
  s.add_enum("input", {"height", "slope", "curvature", "flow", "wetness", "field"})
      .describe("What is compared: height (m), slope (deg), mean curvature (1/m), or the flow, wetness or field input");
  s.add_enum("compare", {"<", ">"}).describe("'>': 1 above the threshold; '<': 1 below it");
  s.add("threshold", ColumnType::Number)
      .range(-1e12, 1e12)
      .unit_of(Unit::InputUnits)
      .describe("The edge, in the input's unit");
  s.add("softness", ColumnType::Number)
      .range(0.0, 1e12)
      .unit_of(Unit::InputUnits)
      .describe("Half-width of the smoothstep around the threshold, in the input's unit; 0: a hard step");
  return s;
}

TableValue default_splat_layers() {
  return table_from_json_text(R"([{"name": "grass", "weight": 1}, {"name": "dirt", "weight": 0.15},
                                  {"name": "rock", "weight": 1}, {"name": "snow", "weight": 1},
                                  {"name": "sand", "weight": 1}])",
                              splat_layer_schema());
}

TableValue default_splat_rules() {
  return table_from_json_text(
      R"([{"layer": "grass", "input": "slope", "compare": "<", "threshold": 30, "softness": 8},
          {"layer": "grass", "input": "height", "compare": ">", "threshold": 6, "softness": 3},
          {"layer": "grass", "input": "height", "compare": "<", "threshold": 1800, "softness": 150},
          {"layer": "dirt", "input": "slope", "compare": "<", "threshold": 42, "softness": 8},
          {"layer": "rock", "input": "slope", "compare": ">", "threshold": 36, "softness": 8},
          {"layer": "snow", "input": "height", "compare": ">", "threshold": 2000, "softness": 150},
          {"layer": "snow", "input": "slope", "compare": "<", "threshold": 50, "softness": 8},
          {"layer": "sand", "input": "height", "compare": "<", "threshold": 5, "softness": 3},
          {"layer": "sand", "input": "slope", "compare": "<", "threshold": 15, "softness": 5}])",
      splat_rule_schema());
}

std::vector<SplatLayer> splat_layers_from_tables(const TableValue& layers, const TableValue& rules) {
  std::vector<SplatLayer> out;
  for (const auto& row : layers.rows) out.push_back({std::get<std::string>(row[0]), std::get<double>(row[1]), {}});
  for (std::size_t r = 0; r < rules.rows.size(); ++r) {
    const auto& row = rules.rows[r];
    const auto& layer = std::get<std::string>(row[0]);
    // A name given to two layers: the rule applies to the first, as a lookup by name would.
    auto it = std::find_if(out.begin(), out.end(), [&](const SplatLayer& l) { return l.name == layer; });
    if (it == out.end())
      throw NodeError("rules[" + std::to_string(r) + "].layer: '" + layer + "' is not a layer of the layers table");
    static const char* const inputs[] = {"height", "slope", "curvature", "flow", "wetness", "field"};
    const auto& input = std::get<std::string>(row[1]);
    SplatTerm t;
    for (int k = 0; k < 6; ++k)
      if (input == inputs[k]) t.input = static_cast<SplatInput>(k);
    t.greater = std::get<std::string>(row[2]) == ">";
    t.threshold = std::get<double>(row[3]);
    t.softness = std::get<double>(row[4]);
    it->terms.push_back(t);
  }
  return out;
}

double splat_term(const SplatTerm& t, double x) {
  if (!std::isfinite(x)) return 0.0;
  double up;
  if (t.softness > 0.0) {
    up = smoothstep01((x - (t.threshold - t.softness)) / (2.0 * t.softness));
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
        for (const auto& t : layers[static_cast<std::size_t>(l)].terms)
          x *= splat_term(t, v[static_cast<int>(t.input)]);
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
      "Generation. A table of layers (name, weight w) and a table of rules, each a term 'input < t ~ s' or "
      "'input > t ~ s' on one layer (soft over [t - s, t + s]; s = 0 is a hard step); inputs height, slope, "
      "curvature, flow, wetness, field. Raw weight = w x product of the terms, then normalized; where all are 0 the "
      "first layer takes the cell. Height bands (H. Zaiz (2022), Procedural Generation of 3D Game Worlds) "
      "are layers with height terms and softness 0.");
  b.input("in", PortType::Heightfield).description("Height, metres");
  b.input("flow", PortType::Heightfield)
      .optional()
      .description("Flow for 'flow' rules (e.g. FlowAccumulation.flow, 0..1)");
  b.input("wetness", PortType::Heightfield)
      .optional()
      .description("Wetness for 'wetness' rules (e.g. FlowAccumulation.wetness)");
  b.input("field", PortType::Heightfield).optional().description("Any field for 'field' rules");
  b.output("out", PortType::Image).description("Weights, one channel per layer (named by the layer), summing to 1");
  b.output("dominant", PortType::Heightfield)
      .description("Id of the heaviest layer (0-based, in layer order)")
      .kind(OutputKind::Scalar);
  b.output("splat0", PortType::Image).description("Layers 0..3 as RGBA");
  b.output("splat1", PortType::Image).description("Layers 4..7 as RGBA (0 where absent)");
  b.param_table("layers", splat_layer_schema(), default_splat_layers())
      .description("The layers in channel order (1 to 8): name and raw weight");
  b.param_table("rules", splat_rule_schema(), default_splat_rules())
      .description("The terms multiplying the layers' weights, one per row: layer, input, < or >, threshold, softness");
  b.execute([](ExecContext& ctx) {
    const auto layers = splat_layers_from_tables(ctx.param<TableValue>("layers"), ctx.param<TableValue>("rules"));
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
