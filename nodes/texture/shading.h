#pragma once
// Shading maps from a height field that artists multiply into colour maps: ambient occlusion and cavity
// from a horizon scan within a radius, and hillshade.
#include <memory>

#include "graph/exec_context.h"
#include "graph/heightfield.h"
#include "graph/image.h"

namespace orogen::texture {

// Per cell and direction, the largest elevation tangent (z(p + r d) - z(p)) / r over distances r up to
// `radius` metres (steps of one sample, growing by 30 % once beyond four samples, and the radius itself),
// on the bilinear surface (clamped at the border). `directions` azimuths evenly spaced from east.
// ao = mean over directions of 1 - sin(max(0, horizon angle));
// cavity = 0.5 - 0.5 * mean over directions of sin(horizon angle): 0.5 on a plane, below in hollows and
// crevices, above on ridges and peaks.
struct HorizonMaps {
  std::shared_ptr<Heightfield> ao, cavity;
};
HorizonMaps horizon_maps(const Heightfield& z, double radius, int directions, const ExecContext* ctx = nullptr);

// Lambert shading of the surface (heights x z_factor) under a light from azimuth (degrees clockwise from
// north) and elevation (degrees above the horizon): max(0, n . l) in [0, 1].
std::shared_ptr<Heightfield> hillshade(const Heightfield& z, double azimuth_deg, double elevation_deg, double z_factor,
                                       const ExecContext* ctx = nullptr);

// A field in [0, 1] as a gray linear RGBA image on its domain: R = G = B = the value, A = 1.
std::shared_ptr<Image> gray_image(const Heightfield& value, const ExecContext* ctx = nullptr);

}  // namespace orogen::texture
