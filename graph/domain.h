#pragma once
// The sampling lattice a request asks for: a world rectangle in metres and its sample counts.
//
// Samples sit on a global lattice: sample (i, j) of a domain is at
//   origin + (first + (i, j)) * spacing
// computed from integers, so a tile cut out of a larger domain (see `subdomain`) has bit-identical sample
// positions to the same samples of the larger one (SeamScape, Appendix B). Border samples are shared: a
// domain of size S with N samples has spacing S / (N - 1).
#include <cstddef>
#include <cstdint>
#include <string>

#include <glm/vec2.hpp>

namespace orogen {

// Limits of a usable domain: below kMinSpacing samples are closer than any terrain needs and coordinates
// stop being distinct; beyond kMaxCoordinate a float cannot tell neighbouring samples apart and lattice
// arithmetic loses its meaning.
inline constexpr double kMinSpacing = 1e-6;     // m
inline constexpr double kMaxCoordinate = 1e12;  // m, |x| and |y| of every sample

struct Domain;
// Empty if `d` is usable (sample counts >= 1, spacing finite and >= kMinSpacing, every sample position
// finite and within kMaxCoordinate), else why not.
std::string check_domain(const Domain& d);

struct Domain {
  glm::dvec2 origin{0.0, 0.0};   // world position of lattice index (0, 0), metres
  glm::dvec2 spacing{1.0, 1.0};  // metres between neighbouring samples
  glm::ivec2 first{0, 0};        // lattice index of this domain's sample (0, 0)
  glm::ivec2 resolution{1, 1};   // sample counts (width, height)

  // A domain covering [origin, origin + size] with `resolution` samples, borders included.
  static Domain from_extent(glm::dvec2 origin, glm::dvec2 size, glm::ivec2 resolution);

  int width() const { return resolution.x; }
  int height() const { return resolution.y; }
  std::size_t sample_count() const {
    return static_cast<std::size_t>(resolution.x) * static_cast<std::size_t>(resolution.y);
  }

  // World x of column i and y of row j (i, j may lie outside the domain).
  double x(int i) const { return origin.x + static_cast<double>(first.x + i) * spacing.x; }
  double y(int j) const { return origin.y + static_cast<double>(first.y + j) * spacing.y; }
  glm::dvec2 position(int i, int j) const { return {x(i), y(j)}; }

  glm::dvec2 min_corner() const { return position(0, 0); }
  glm::dvec2 max_corner() const { return position(resolution.x - 1, resolution.y - 1); }
  glm::dvec2 size() const { return max_corner() - min_corner(); }

  // Continuous sample coordinates (column, row) of a world position; integer at samples.
  glm::dvec2 to_sample(glm::dvec2 world) const {
    return {(world.x - origin.x) / spacing.x - first.x, (world.y - origin.y) / spacing.y - first.y};
  }

  // The w x h samples starting at (i0, j0) of this domain, on the same lattice.
  Domain subdomain(int i0, int j0, int w, int h) const;

  // The same world rectangle sampled at another resolution (a new lattice).
  Domain resampled(glm::ivec2 new_resolution) const;

  bool operator==(const Domain&) const = default;
  std::string describe() const;
};

}  // namespace orogen
