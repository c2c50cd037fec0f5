#pragma once
// Normalisation about sea level (the last step of the Georgia Tech report's heightmap, §IV-F3): heights above
// `sea_level` are scaled so the highest becomes `height`, heights below so the deepest becomes -`depth`; sea
// level maps to 0, so the coastline does not move.
#include <memory>

#include "graph/heightfield.h"

namespace orogen {
class ExecContext;
}

namespace orogen::island {

struct SeaLevelParams {
  double sea_level = 0.0;  // m, in the input
  double height = 1000.0;  // m, of the highest sample in the output
  double depth = 200.0;    // m, of the deepest sample in the output (positive)
};

std::shared_ptr<Heightfield> sea_level_normalize(const Heightfield& in, const SeaLevelParams& p,
                                                 const ExecContext* ctx = nullptr);

}  // namespace orogen::island
