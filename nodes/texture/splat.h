#pragma once
// Splat weights: material layers (grass, rock, dirt, snow, sand, ...) from rules on height, slope,
// curvature, flow, wetness or any field, with soft edges, normalised to sum to 1 per cell. After the
// height-and-steepness rules of L. Potter (2017), Generating a Virtual Forest Environment using Procedural
// Content Generation (section 3.4), written as smoothstep bands.
//
// Two tables: `layers` (name, weight) and `rules`, one term per row (layer, input, compare, threshold,
// softness) with input height (m) | slope (deg) | curvature (mean curvature, 1/m, convex > 0) | flow |
// wetness | field. A term `x > t ~ s` is smoothstep over [t - s, t + s] (a hard step at t when s = 0);
// `x < t ~ s` is one minus that. A layer's raw weight is w (default 1) times the product of its terms; a layer without
// terms is a constant background. Weights are divided by their sum; where every raw weight is 0 the first layer takes
// it all. Non-finite inputs make a term 0.
#include <memory>
#include <string>
#include <vector>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/table_value.h"

namespace orogen::texture {

enum class SplatInput { Height, Slope, Curvature, Flow, Wetness, Field };

struct SplatTerm {
  SplatInput input = SplatInput::Height;
  bool greater = true;
  double threshold = 0.0, softness = 0.0;
};

struct SplatLayer {
  std::string name;
  double weight = 1.0;
  std::vector<SplatTerm> terms;
};

inline constexpr int kMaxSplatLayers = 8;

// The node's tables and their defaults (grass, dirt, rock, snow, sand).
TableSchema splat_layer_schema();
TableSchema splat_rule_schema();
TableValue default_splat_layers();
TableValue default_splat_rules();
// The layers in table order, each with its rules in table order. Throws NodeError naming the row of a rule
// whose layer is not in `layers`.
std::vector<SplatLayer> splat_layers_from_tables(const TableValue& layers, const TableValue& rules);

// 0..1 factor of one term for value x.
double splat_term(const SplatTerm& t, double x);

struct SplatInputs {
  const Heightfield* height = nullptr;  // required
  const Heightfield* flow = nullptr;
  const Heightfield* wetness = nullptr;
  const Heightfield* field = nullptr;
};

struct SplatResult {
  std::shared_ptr<Image> weights;         // one channel per layer, named by the layer
  std::shared_ptr<Heightfield> dominant;  // argmax layer id (lowest id on ties)
  std::shared_ptr<Image> splat[2];        // RGBA packs of layers 0..3 and 4..7 (missing layers 0)
};
SplatResult splat_weights(const SplatInputs& in, const std::vector<SplatLayer>& layers,
                          const ExecContext* ctx = nullptr);

}  // namespace orogen::texture
