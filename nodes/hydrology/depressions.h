#pragma once
// Depression handling on heightfields: FillDepressions (fill or carve, lakes kept), Lakes (every depression as
// a lake with a flat surface) and FloodFill (a lake from a seed point), over the routing core.
#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec2.hpp>

#include "graph/exec_context.h"
#include "graph/heightfield.h"

namespace orogen::hydrology {

// 8-connected components of the cells where mask[c] != 0, labelled 1, 2, ... in order of their first cell in
// row-major order (0 elsewhere). Returns the label count.
int label_components(int nx, int ny, const std::vector<std::uint8_t>& mask, std::vector<std::int32_t>& label);

struct FillParams {
  bool carve = false;      // breach (carve) depressions instead of filling them
  bool epsilon = true;     // give filled areas a drainage gradient (FlatMode::Epsilon) instead of flats
  double max_depth = 0.0;  // carve: depressions at most this deep (m) are filled and kept as lakes
  bool lake_maps = true;   // also the depth and lake id maps and the lake count; false leaves them null (and
                           // fill, or carve without kept lakes, is then the routing core's call alone)
};

struct FillResult {
  std::shared_ptr<Heightfield> out;      // filled (or carved) height, m
  std::shared_ptr<Heightfield> depth;    // water depth of the lakes (flat surface minus ground), m
  std::shared_ptr<Heightfield> lake_id;  // 1, 2, ... per lake, 0 on dry ground
  int lakes = 0;
};

FillResult fill_depressions(const Heightfield& in, const FillParams& p, const ExecContext* ctx = nullptr);

struct LakesParams {
  double min_depth = 0.0;  // m: shallower depressions are not lakes
  double min_area = 0.0;   // m^2: smaller depressions are not lakes
  bool lake_maps = true;   // also the depth and lake id maps; false leaves them null
};

// Every closed depression, filled to its spill level: out = water surface where there is a lake, the ground
// elsewhere; depth; lake_id.
FillResult lakes(const Heightfield& in, const LakesParams& p, const ExecContext* ctx = nullptr);

struct FloodFillParams {
  glm::dvec2 seed{0.0, 0.0};  // world position, m
  bool spill = true;          // fill to the spill level of the seed's depression (else to `level`)
  double level = 0.0;         // m
};

struct FloodFillResult {
  std::shared_ptr<Heightfield> out;    // water surface in the lake, ground elsewhere, m
  std::shared_ptr<Heightfield> depth;  // m
  std::shared_ptr<Heightfield> mask;   // 1 in the lake
  double level = 0.0;                  // the water level used
};

// Every cell 8-connected to the seed's nearest sample whose ground is below the level (Long 2016 §3.4).
FloodFillResult flood_fill(const Heightfield& in, const FloodFillParams& p, const ExecContext* ctx = nullptr);

}  // namespace orogen::hydrology
