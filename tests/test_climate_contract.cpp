// Resolution independence of the climate and texture nodes: the same terrain at 65^2 and 129^2 samples of one
// domain gives the same values on the common samples (within a tolerance set by what the node computes:
// exact for point-wise ones, close for derivatives, mostly equal for shadows).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

#include "evaluator/run_node.h"
#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/table_json.h"
#include "nodes/texture/splat.h"

namespace orogen {
namespace {

double terrain(double x, double y) {
  return 300.0 + 180.0 * std::sin(x / 900.0) * std::cos(y / 700.0) + 90.0 * std::sin((x + 2 * y) / 1300.0);
}

HeightfieldPtr field(const Domain& d) {
  auto h = std::make_shared<Heightfield>(d);
  for (int j = 0; j < d.height(); ++j)
    for (int i = 0; i < d.width(); ++i) h->at(i, j) = static_cast<float>(terrain(d.x(i), d.y(j)));
  return h;
}

// Values of output `k` at coarse sample (i, j) (all channels).
std::vector<float> values(const NodeRun& r, std::size_t k, int i, int j) {
  if (const auto* f = std::get_if<HeightfieldPtr>(&r.outputs.at(k))) return {(*f)->at(i, j)};
  const auto& img = std::get<ImagePtr>(r.outputs.at(k));
  return std::vector<float>(img->pixel(i, j), img->pixel(i, j) + img->channels);
}

struct Case {
  std::string type;
  std::map<std::string, ParamValue> params;
  std::size_t output;
  double tolerance;       // absolute, per value
  double allowed_misses;  // fraction of values allowed beyond the tolerance (shadow edges, thresholds)
};

TEST(ClimateContract, SameTerrainAtTwoResolutions) {
  const Domain coarse = Domain::from_extent({0, 0}, {6400, 6400}, {65, 65});
  const Domain fine = coarse.resampled({129, 129});
  const Case cases[] = {
      {"Temperature", {}, 0, 1e-4, 0.0},
      {"SoilHumidity", {{"max_slope", 12.0}}, 0, 1e-3, 0.02},
      {"SunIllumination", {{"time_step", 0.5}}, 0, 0.51, 0.03},  // lit hours: one interval near shadow edges
      {"SunIllumination", {{"time_step", 0.5}}, 1, 25.0, 0.03},  // mean irradiance, W/m^2
      {"SplatWeights",
       {{"layers", table_from_json_text(R"([{"name": "low", "weight": 1}, {"name": "high", "weight": 1},
                                            {"name": "steep", "weight": 1}])",
                                        texture::splat_layer_schema())},
        {"rules", table_from_json_text(
                      R"([{"layer": "low", "input": "height", "compare": "<", "threshold": 300, "softness": 60},
                          {"layer": "high", "input": "height", "compare": ">", "threshold": 300, "softness": 60},
                          {"layer": "steep", "input": "slope", "compare": ">", "threshold": 10, "softness": 4}])",
                      texture::splat_rule_schema())}},
       0,
       0.05,
       0.01},
      {"Hillshade", {}, 0, 0.02, 0.0},
      {"AmbientOcclusion", {{"radius", 800.0}}, 0, 0.03, 0.01},
      {"Cavity", {{"radius", 400.0}}, 0, 0.03, 0.01},
  };
  for (const auto& c : cases) {
    const auto a = run_node(c.type, coarse, c.params, {{"in", PortValue(field(coarse))}});
    const auto b = run_node(c.type, fine, c.params, {{"in", PortValue(field(fine))}});
    int misses = 0, total = 0;
    double worst = 0.0;
    for (int j = 1; j < 64; ++j)
      for (int i = 1; i < 64; ++i) {
        const auto va = values(a, c.output, i, j), vb = values(b, c.output, 2 * i, 2 * j);
        for (std::size_t k = 0; k < va.size(); ++k) {
          const double e = std::abs(double(va[k]) - vb[k]);
          worst = std::max(worst, e);
          misses += e > c.tolerance;
          ++total;
        }
      }
    EXPECT_LE(misses, c.allowed_misses * total) << c.type << " output " << c.output << ": worst " << worst;
  }
}

}  // namespace
}  // namespace orogen
