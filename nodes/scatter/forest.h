#pragma once
// Shade under a placed canopy and the forest life cycle.
#include <cstdint>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "graph/heightfield.h"
#include "graph/points.h"

namespace orogen {

class WorkPoll;

class ExecContext;

// Direction toward the sun (x east, y north, z up) from its azimuth (degrees clockwise from north) and
// elevation (degrees above the horizon).
glm::dvec3 sun_direction(double azimuth_deg, double elevation_deg);

struct CanopyParams {
  double crown_radius = 3.0;  // m, at scale 1 (times the point's scale x)
  double crown_height = 8.0;  // m, height of the crown's centre above the point, at scale 1 (times scale z)
  glm::dvec3 sun{0.0, -0.7071067811865476, 0.7071067811865476};  // toward the sun, unit
  // m: a crown whose center lies farther than this from a point, measured horizontally, does not shade it (0: any
  // distance). A bound makes the shade of a point depend only on the casters within it: the node's reach.
  double max_shadow_distance = 0.0;
};

// The casters' crowns as spheres, indexed for shadow queries along the sun direction.
class Canopy {
 public:
  Canopy(const Points& casters, const CanopyParams& p);
  // True if the ray from (x, y, z) toward the sun meets a crown (a point inside a crown is shaded).
  // A poll, if given, counts one unit per march step (the march of one ray can be millions of steps).
  bool shaded(double x, double y, double z, WorkPoll* poll = nullptr) const;
  // The most march steps one ray takes (the index's rectangle crossed diagonally).
  double max_march() const;

 private:
  struct Sphere {
    double x, y, z, r;
  };
  std::vector<Sphere> spheres_;
  std::vector<std::vector<int>> cells_;
  double cell_ = 1.0, x0_ = 0.0, y0_ = 0.0, max_r_ = 0.0, max_top_ = 0.0, max_distance_ = 0.0;
  int nx_ = 0, ny_ = 0;
  glm::dvec3 sun_;
};

// Shadow map of a canopy over a domain (1 shaded, 0 lit), on the terrain `height` (or z = 0).
Heightfield shade_map(const Domain& d, const Canopy& canopy, const Heightfield* height,
                      const ExecContext* ctx = nullptr);

enum class ShadePreference { Shade, Sun, Any };

struct ShadePlacementParams {
  CanopyParams canopy;  // canopy.sun: toward the sun; a sun at or below the horizon (z <= 1e-6) is night
  ShadePreference preference = ShadePreference::Shade;  // which candidates are kept
};

struct ShadePlacementResult {
  Points points;      // the kept candidates in input order, attribute "shade" (1 shaded, 0 lit)
  Heightfield shade;  // shadow map on the domain, 1 shaded / 0 lit
};

// Shade-driven placement (Potter 2017): each candidate is shaded when the ray toward the sun meets a
// caster's crown (every candidate at night); the kept ones carry their rotation, scale, class and attributes.
// The shadow map lies on `d`, on the terrain `height` (or z = 0); all 1 at night.
ShadePlacementResult shade_placement(const Points& candidates, const Points& casters, const Domain& d,
                                     const Heightfield* height, const ShadePlacementParams& p,
                                     const ExecContext* ctx = nullptr);

struct LifeCycleParams {
  int years = 50;
  double max_age = 80.0;       // years: trees older die
  double maturity_age = 20.0;  // years to grow from min_scale to max_scale (linear)
  double min_scale = 0.2, max_scale = 1.0;
  double seed_distance = 12.0;    // m: seeds land uniformly within this distance of the parent
  double seed_probability = 0.1;  // per mature tree and year (a dying tree always drops 1 or 2)
  double competition = 6.0;       // m at scale 1: trees keep competition * (s_i + s_j) / 2 apart; the smaller dies
  const Heightfield* suitability = nullptr;  // germination only where >= 0.5 (optional)
  glm::dvec2 lo{0, 0}, hi{0, 0};             // seeds outside the rectangle are lost
  std::uint64_t seed = 0;
};

// Runs the years; the input points are the initial trees (attribute "age" if present, else an age hashed
// in [0, max_age)). Output: the survivors with attributes "age" (years) and scale (uniform) from their age,
// class id inherited from the parent, yaw hashed. Deterministic (sequential, fixed order).
Points forest_life_cycle(const Points& initial, const LifeCycleParams& p, const ExecContext* ctx = nullptr);

}  // namespace orogen
