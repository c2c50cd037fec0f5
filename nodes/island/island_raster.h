#pragma once
// Rendering a polygon map into fields on a domain (Patel 2010; the Georgia Tech report §IV-F).
//
// Every sample looks up the map at its world position displaced by two fractal Perlin fields of amplitude
// `perturb_distance` (the report's noisy lookup that hides the straight cell edges; 0 = exact lookup). The
// lookup finds the cell (nearest site: the cells are the sites' Voronoi cells) and, inside it, the triangle
// (site, corner k, corner k+1) of the cell's fan; elevation and moisture are interpolated linearly over it
// from the corners and the cell centre (the cell's value). Along an edge between two corners the value is
// their linear blend, so a river edge never climbs. Biome id, water, ocean and lake come from the cell;
// the river mask is the coverage of capsules along every river edge (corner -> downstream corner) of width
// river_width * sqrt(volume), anti-aliased over one sample and looked up at the same displaced position.
#include <cstdint>
#include <memory>

#include "graph/heightfield.h"
#include "graph/image.h"
#include "graph/polygon_map.h"

namespace orogen {
class ExecContext;
}

namespace orogen::island {

struct RasterParams {
  double perturb_distance = 40.0;       // m, amplitude of the lookup displacement
  double perturb_feature_size = 400.0;  // m, feature size of the displacement noise
  double river_width = 6.0;             // m, width of a river of volume 1 (grows with sqrt(volume))
  std::uint64_t seed = 0;
};

struct RasterResult {
  std::shared_ptr<Heightfield> elevation, moisture, biome, water, ocean, lake, river, roughness, amplitude;
  std::shared_ptr<Image> color;  // linear RGBA: biome colour, rivers drawn over it
};

RasterResult rasterize_polygon_map(const PolygonMap& map, const Domain& domain, const RasterParams& p,
                                   const ExecContext* ctx = nullptr);

// The cell containing world position p (nearest site), -1 for an empty map. Exposed for tests.
class CellLocator {
 public:
  explicit CellLocator(const PolygonMap& map);
  int find(glm::dvec2 p) const;

 private:
  const PolygonMap& map_;
  glm::dvec2 lo_{0.0}, cell_{1.0};
  int gw_ = 1, gh_ = 1;
  std::vector<int> start_, items_;
};

}  // namespace orogen::island
