#include "nodes/landform/landform_common.h"

#include <cstdio>

#include "nodes/noise/fbm.h"

namespace orogen::landform {

namespace {
noise::FbmParams fbm_params(double feature_size, int octaves, bool ridged, std::uint64_t seed) {
  noise::FbmParams p;
  p.basis = noise::Basis::Perlin;
  p.mode = ridged ? noise::FractalMode::Ridged : noise::FractalMode::Fbm;
  p.feature_size = feature_size;
  p.amplitude = 1.0;
  p.octaves = octaves;
  p.seed = seed;
  return p;
}
}  // namespace

Heightfield unit_noise(const Domain& domain, double feature_size, int octaves, bool ridged, std::uint64_t seed,
                       const ExecContext* ctx) {
  return noise::fbm(domain, fbm_params(feature_size, octaves, ridged, seed), {}, ctx);
}

double unit_noise_at(double x, double y, double feature_size, int octaves, bool ridged, std::uint64_t seed) {
  return noise::evaluate_noise_reference(noise::fbm_plan(fbm_params(feature_size, octaves, ridged, seed)), x, y);
}

void require(bool ok, const std::string& node, const std::string& message) {
  if (!ok) throw NodeError(node + ": " + message);
}

std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace orogen::landform
