#include "editor/model/preview_image.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "editor/model/scene_preview.h"
#include "graph/polygon_map.h"
#include "graph/scene.h"
#include "nodes/common/categorical_palette.h"
#include "nodes/common/color_space.h"

namespace orogen::editor {

namespace {

struct Stop {
  double t;
  glm::vec3 c;
};

// Hypsometric tints: deep water, shallow water, lowland green, upland ochre, rock brown, snow.
constexpr std::array<Stop, 7> kTerrain{{{0.00, {0.11f, 0.20f, 0.42f}},
                                        {0.18, {0.25f, 0.47f, 0.70f}},
                                        {0.22, {0.36f, 0.56f, 0.33f}},
                                        {0.45, {0.62f, 0.70f, 0.40f}},
                                        {0.68, {0.72f, 0.60f, 0.42f}},
                                        {0.86, {0.56f, 0.46f, 0.40f}},
                                        {1.00, {0.97f, 0.97f, 0.98f}}}};
// Matplotlib's viridis at nine evenly spaced points (sRGB).
constexpr std::array<Stop, 9> kViridis{{{0.000, {0.267f, 0.005f, 0.329f}},
                                        {0.125, {0.283f, 0.141f, 0.458f}},
                                        {0.250, {0.254f, 0.265f, 0.530f}},
                                        {0.375, {0.207f, 0.372f, 0.553f}},
                                        {0.500, {0.164f, 0.471f, 0.558f}},
                                        {0.625, {0.128f, 0.567f, 0.551f}},
                                        {0.750, {0.135f, 0.659f, 0.518f}},
                                        {0.875, {0.478f, 0.821f, 0.318f}},
                                        {1.000, {0.993f, 0.906f, 0.144f}}}};

// Diverging blue - white - red (ColorBrewer RdBu, reversed so negative is blue).
constexpr std::array<Stop, 7> kDiverging{{{0.000, {0.020f, 0.188f, 0.380f}},
                                          {0.170, {0.129f, 0.400f, 0.675f}},
                                          {0.330, {0.573f, 0.773f, 0.871f}},
                                          {0.500, {0.969f, 0.969f, 0.969f}},
                                          {0.670, {0.957f, 0.647f, 0.510f}},
                                          {0.830, {0.839f, 0.376f, 0.302f}},
                                          {1.000, {0.404f, 0.000f, 0.122f}}}};
// Water depth: dry land dark gray, the shallowest water pale cyan, deepening to navy.
constexpr std::array<Stop, 4> kWater{{{0.000, {0.18f, 0.18f, 0.19f}},
                                      {0.002, {0.70f, 0.88f, 0.95f}},
                                      {0.400, {0.20f, 0.50f, 0.80f}},
                                      {1.000, {0.04f, 0.12f, 0.38f}}}};

template <std::size_t N>
glm::vec3 lookup(const std::array<Stop, N>& stops, double t) {
  if (t <= stops.front().t) return stops.front().c;
  for (std::size_t k = 1; k < N; ++k)
    if (t <= stops[k].t) {
      const float f = static_cast<float>((t - stops[k - 1].t) / (stops[k].t - stops[k - 1].t));
      return stops[k - 1].c + (stops[k].c - stops[k - 1].c) * f;
    }
  return stops.back().c;
}

std::uint8_t to_byte(float v) { return static_cast<std::uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f); }

}  // namespace

Heightfield image_channel(const Image& image, int channel) {
  Heightfield h(image.domain);
  if (channel < 0 || channel >= image.channels) return h;
  for (std::size_t q = 0; q < h.data.size(); ++q)
    h.data[q] = image.data[q * static_cast<std::size_t>(image.channels) + static_cast<std::size_t>(channel)];
  return h;
}

glm::vec3 colormap(ColorMap map, double t) {
  t = std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0);
  switch (map) {
    case ColorMap::Gray:
      return glm::vec3(static_cast<float>(t));
    case ColorMap::Terrain:
      return lookup(kTerrain, t);
    case ColorMap::Viridis:
      return lookup(kViridis, t);
    case ColorMap::Diverging:
      return lookup(kDiverging, t);
    case ColorMap::Water:
      return lookup(kWater, t);
    case ColorMap::Categorical:
      return categorical_srgb(std::lround(t * 11.0));  // ids 0..11 over the range
  }
  return glm::vec3(0.0f);
}

ValueRange value_range(const Heightfield& field) {
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (float v : field.data)
    if (std::isfinite(v)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  if (!(lo <= hi)) return {0.0f, 1.0f};
  if (hi - lo < 1e-6f * std::max(1.0f, std::abs(lo))) return {lo - 0.5f, lo + 0.5f};
  return {lo, hi};
}

std::vector<float> hillshade(const Heightfield& field, double azimuth_deg, double altitude_deg, double z_factor) {
  const int w = field.width(), h = field.height();
  const double az = azimuth_deg * M_PI / 180.0, alt = altitude_deg * M_PI / 180.0;
  const float lx = static_cast<float>(std::sin(az) * std::cos(alt)),
              ly = static_cast<float>(std::cos(az) * std::cos(alt));
  const float lz = static_cast<float>(std::sin(alt));
  const float kx = static_cast<float>(z_factor / field.domain.spacing.x),
              ky = static_cast<float>(z_factor / field.domain.spacing.y);
  std::vector<float> out(field.data.size(), 1.0f);
  tbb::parallel_for(0, h, [&](int j) {
    // Central differences inside, one-sided at the borders.
    const int j0 = std::max(j - 1, 0), j1 = std::min(j + 1, h - 1);
    const float fy = j1 > j0 ? ky / static_cast<float>(j1 - j0) : 0.0f;
    const float* up = field.data.data() + field.index(0, j1);
    const float* down = field.data.data() + field.index(0, j0);
    const float* row = field.data.data() + field.index(0, j);
    float* dst = out.data() + field.index(0, j);
    for (int i = 0; i < w; ++i) {
      const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, w - 1);
      const float dzdx = i1 > i0 ? (row[i1] - row[i0]) * kx / static_cast<float>(i1 - i0) : 0.0f;
      const float dzdy = (up[i] - down[i]) * fy;
      // Normal (-dzdx, -dzdy, 1), normalised, dotted with the light.
      const float shade = (lz - dzdx * lx - dzdy * ly) / std::sqrt(dzdx * dzdx + dzdy * dzdy + 1.0f);
      dst[i] = std::isfinite(shade) ? std::max(0.0f, shade) : 1.0f;
    }
  });
  return out;
}

ValueRange style_range(const Heightfield& field, const HeightfieldStyle& style) {
  if (style.range) return *style.range;
  const ValueRange r = value_range(field);
  if (!style.symmetric) return r;
  const float m = std::max(std::abs(r.lo), std::abs(r.hi));
  return m > 0.0f && std::isfinite(m) ? ValueRange{-m, m} : ValueRange{-1.0f, 1.0f};
}

HeightfieldStyle style_for(OutputKind kind) {
  HeightfieldStyle s;
  switch (kind) {
    case OutputKind::Auto:
    case OutputKind::Height:
      break;
    case OutputKind::Mask:
      s.map = ColorMap::Gray;
      s.hillshade = false;
      s.range = ValueRange{0.0f, 1.0f};
      break;
    case OutputKind::Signed:
      s.map = ColorMap::Diverging;
      s.hillshade = false;
      s.symmetric = true;
      break;
    case OutputKind::Scalar:
      s.map = ColorMap::Viridis;
      s.hillshade = false;
      break;
    case OutputKind::WaterDepth:
      s.map = ColorMap::Water;
      s.hillshade = false;
      break;
  }
  return s;
}

OutputKind resolve_output_kind(const Graph& graph, const std::string& node_id, const std::string& port) {
  std::string id = node_id, name = port;
  // Follows primary inputs upstream; a graph is acyclic, the bound only guards against a malformed one.
  for (std::size_t hops = 0; hops <= graph.nodes().size(); ++hops) {
    const Node* n = graph.find(id);
    if (!n) return OutputKind::Height;
    const PortDecl* out = n->type->find_output(name);
    if (!out || out->type != PortType::Heightfield) return OutputKind::Height;
    if (out->kind != OutputKind::Auto) return out->kind;
    if (name == "mask" || (name.size() > 5 && name.compare(name.size() - 5, 5, "_mask") == 0)) return OutputKind::Mask;
    const PortRef* from = nullptr;
    for (const char* primary : {"in", "a"})
      if (auto it = n->inputs.find(primary); it != n->inputs.end()) {
        from = &it->second;
        break;
      }
    if (!from)
      for (const auto& in : n->type->inputs)
        if (in.type == PortType::Heightfield)
          if (auto it = n->inputs.find(in.name); it != n->inputs.end()) {
            from = &it->second;
            break;
          }
    if (!from) return OutputKind::Height;
    id = from->node;
    name = from->port;
  }
  return OutputKind::Height;
}

PreviewPixels render_heightfield(const Heightfield& field, const HeightfieldStyle& style) {
  PreviewPixels px;
  px.width = field.width();
  px.height = field.height();
  px.rgba.resize(static_cast<std::size_t>(px.width) * px.height * 4);
  const ValueRange range = style_range(field, style);
  // The colour map as a table: one lookup per sample instead of a search through the stops.
  constexpr int kTable = 1024;
  std::array<glm::vec3, kTable> table;
  for (int k = 0; k < kTable; ++k) table[static_cast<std::size_t>(k)] = colormap(style.map, (k + 0.5) / kTable);
  const float to_index = static_cast<float>(kTable) / (range.hi - range.lo);
  std::vector<float> shade;
  if (style.hillshade) shade = hillshade(field);
  // Rows in parallel: the UI thread waits for this after every evaluation.
  tbb::parallel_for(0, px.height, [&](int r) {
    const int j = px.height - 1 - r;
    std::uint8_t* p = &px.rgba[static_cast<std::size_t>(r) * px.width * 4];
    for (int i = 0; i < px.width; ++i, p += 4) {
      const float v = field.at(i, j);
      glm::vec3 c{1.0f, 0.0f, 1.0f};  // magenta marks NaN and infinity
      if (std::isfinite(v))
        c = style.map == ColorMap::Categorical && std::abs(v) < 1e9f
                ? categorical_srgb(std::lround(v))
                : table[static_cast<std::size_t>(
                      std::clamp(static_cast<int>((v - range.lo) * to_index), 0, kTable - 1))];
      // Hillshade as a soft multiply: ambient 0.35 keeps valleys readable.
      if (style.hillshade) c *= 0.35f + 0.75f * shade[field.index(i, j)];
      p[0] = to_byte(c.r);
      p[1] = to_byte(c.g);
      p[2] = to_byte(c.b);
      p[3] = 255;
    }
  });
  return px;
}

PreviewPixels render_water_over_terrain(const Heightfield& terrain, const Heightfield& depth) {
  PreviewPixels px = render_heightfield(terrain, style_for(OutputKind::Height));
  const bool same = depth.width() == terrain.width() && depth.height() == terrain.height() &&
                    depth.domain.min_corner() == terrain.domain.min_corner() &&
                    depth.domain.max_corner() == terrain.domain.max_corner();
  float max_depth = 0.0f;
  for (float v : depth.data)
    if (std::isfinite(v)) max_depth = std::max(max_depth, v);
  if (max_depth <= 0.0f) return px;
  tbb::parallel_for(0, px.height, [&](int r) {
    const int j = px.height - 1 - r;
    for (int i = 0; i < px.width; ++i) {
      const float d = same ? depth.at(i, j) : depth.sample_world(terrain.domain.x(i), terrain.domain.y(j));
      if (!(d > 0.0f)) continue;
      const float t = std::min(d / max_depth, 1.0f);
      const glm::vec3 water(0.25f - 0.17f * t, 0.55f - 0.25f * t, 0.78f - 0.18f * t);
      const float a = 0.55f + 0.4f * t;
      std::uint8_t* p = &px.rgba[(static_cast<std::size_t>(r) * px.width + i) * 4];
      for (int k = 0; k < 3; ++k) p[k] = to_byte((p[k] / 255.0f) * (1.0f - a) + water[k] * a);
    }
  });
  return px;
}

PreviewPixels render_image(const Image& image) {
  PreviewPixels px;
  px.width = image.width();
  px.height = image.height();
  px.rgba.resize(static_cast<std::size_t>(px.width) * px.height * 4);
  const int n = image.channels;
  tbb::parallel_for(0, px.height, [&](int r) {
    const int j = px.height - 1 - r;
    for (int i = 0; i < px.width; ++i) {
      const float* s = image.pixel(i, j);
      float c[4] = {0, 0, 0, 1};
      if (n == 1 || n == 2) {
        c[0] = c[1] = c[2] = s[0];
        if (n == 2) c[3] = s[1];
      } else if (n >= 3) {
        c[0] = s[0];
        c[1] = s[1];
        c[2] = s[2];
        if (n >= 4) c[3] = s[3];
      }
      std::uint8_t* p = &px.rgba[(static_cast<std::size_t>(r) * px.width + i) * 4];
      for (int k = 0; k < 3; ++k) p[k] = to_byte(linear_to_srgb(c[k]));
      p[3] = to_byte(c[3]);
    }
  });
  return px;
}

namespace {

constexpr std::uint8_t kThumbBackground[3] = {24, 25, 28};

// The pixel grid a world rectangle maps to, and the mapping.
struct PixelFrame {
  int width = 1, height = 1;
  glm::dvec2 lo{0.0}, size{1.0};
  PixelFrame(const Domain& domain, int max_side) {
    lo = domain.min_corner();
    size = glm::max(domain.max_corner() - lo, glm::dvec2(1e-9));
    max_side = std::max(max_side, 1);
    if (size.x >= size.y) {
      width = max_side;
      height = std::max(1, static_cast<int>(std::lround(max_side * size.y / size.x)));
    } else {
      height = max_side;
      width = std::max(1, static_cast<int>(std::lround(max_side * size.x / size.y)));
    }
  }
  // Continuous pixel coordinates (x right, y down; the top row shows the highest world y).
  glm::dvec2 to_pixel(double x, double y) const {
    return {(x - lo.x) / size.x * width, (1.0 - (y - lo.y) / size.y) * height};
  }
  double pixels_per_metre() const { return width / size.x; }
  PreviewPixels blank() const {
    PreviewPixels px;
    px.width = width;
    px.height = height;
    px.rgba.resize(static_cast<std::size_t>(width) * height * 4);
    for (std::size_t k = 0; k < px.rgba.size(); k += 4) {
      px.rgba[k] = kThumbBackground[0];
      px.rgba[k + 1] = kThumbBackground[1];
      px.rgba[k + 2] = kThumbBackground[2];
      px.rgba[k + 3] = 255;
    }
    return px;
  }
};

void put(PreviewPixels& px, int i, int j, glm::vec3 c) {
  if (i < 0 || j < 0 || i >= px.width || j >= px.height) return;
  std::uint8_t* p = &px.rgba[(static_cast<std::size_t>(j) * px.width + i) * 4];
  p[0] = static_cast<std::uint8_t>(std::lround(std::clamp(c.r, 0.0f, 1.0f) * 255.0f));
  p[1] = static_cast<std::uint8_t>(std::lround(std::clamp(c.g, 0.0f, 1.0f) * 255.0f));
  p[2] = static_cast<std::uint8_t>(std::lround(std::clamp(c.b, 0.0f, 1.0f) * 255.0f));
  p[3] = 255;
}

}  // namespace

PreviewPixels render_points(const Points& points, const Domain& domain, int max_side) {
  const PixelFrame frame(domain, max_side);
  PreviewPixels px = frame.blank();
  // Sparse sets get 2 x 2 dots so they read at thumbnail size.
  const int dot = points.size() * 8 < static_cast<std::size_t>(frame.width) * frame.height ? 2 : 1;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const glm::vec3 p = points.position[k];
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) continue;
    const glm::dvec2 q = frame.to_pixel(p.x, p.y);
    const int i = static_cast<int>(std::floor(q.x - (dot - 1) * 0.5)),
              j = static_cast<int>(std::floor(q.y - (dot - 1) * 0.5));
    const glm::vec3 c(marker_color(k < points.class_id.size() ? points.class_id[k] : 0));
    for (int dj = 0; dj < dot; ++dj)
      for (int di = 0; di < dot; ++di) put(px, i + di, j + dj, c);
  }
  return px;
}

PreviewPixels render_curves(const Curves& curves, const Domain& domain, int max_side) {
  const PixelFrame frame(domain, max_side);
  PreviewPixels px = frame.blank();
  float max_width = 0.0f;
  for (const auto& curve : curves.curves)
    for (float w : curve.width) max_width = std::max(max_width, w);
  const double ppm = frame.pixels_per_metre();
  for (const auto& curve : curves.curves) {
    auto width_at = [&](std::size_t k) { return k < curve.width.size() ? curve.width[k] : 0.0f; };
    for (std::size_t k = 0; k + 1 < curve.points.size(); ++k) {
      const glm::vec3 a3 = curve.points[k], b3 = curve.points[k + 1];
      if (!std::isfinite(a3.x + a3.y + b3.x + b3.y)) continue;
      const glm::dvec2 a = frame.to_pixel(a3.x, a3.y), b = frame.to_pixel(b3.x, b3.y);
      const float w = 0.5f * (width_at(k) + width_at(k + 1));
      const float t = max_width > 0.0f ? std::clamp(w / max_width, 0.0f, 1.0f) : 0.0f;
      const glm::vec3 c(0.55f - 0.45f * t, 0.85f - 0.4f * t, 1.0f - 0.1f * t);
      const double radius = std::max(0.75, 0.5 * w * ppm);  // thin lines stay connected
      // Every pixel within `radius` of the segment (its bounding box, clipped to the picture).
      const int i0 = std::max(0, static_cast<int>(std::floor(std::min(a.x, b.x) - radius)));
      const int i1 = std::min(px.width - 1, static_cast<int>(std::ceil(std::max(a.x, b.x) + radius)));
      const int j0 = std::max(0, static_cast<int>(std::floor(std::min(a.y, b.y) - radius)));
      const int j1 = std::min(px.height - 1, static_cast<int>(std::ceil(std::max(a.y, b.y) + radius)));
      const glm::dvec2 d = b - a;
      const double len2 = glm::dot(d, d);
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
          const glm::dvec2 q(i + 0.5, j + 0.5);
          const double s = len2 > 0.0 ? std::clamp(glm::dot(q - a, d) / len2, 0.0, 1.0) : 0.0;
          const glm::dvec2 e = q - (a + s * d);
          if (glm::dot(e, e) <= radius * radius) put(px, i, j, c);
        }
    }
  }
  return px;
}

namespace {

// 4 significant digits, and whole metres from 1 km on (4096 m, not 4.096e+03 m).
std::string metres(double m) {
  char buf[48];
  std::snprintf(buf, sizeof buf, std::abs(m) >= 1000.0 ? "%.0f m" : "%.4g m", m);
  return buf;
}

std::string raster(const Domain& d, const char* samples) {
  std::string s = std::to_string(d.width()) + " x " + std::to_string(d.height()) + " " + samples + ", spacing " +
                  metres(d.spacing.x);
  if (d.spacing.y != d.spacing.x) s += " x " + metres(d.spacing.y);
  return s;
}

std::string count(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

std::string describe_preview_value(const PortValue& value, const Heightfield* backdrop) {
  std::string s;
  if (auto* h = std::get_if<HeightfieldPtr>(&value); h && *h) return raster((*h)->domain, "samples");
  if (auto* im = std::get_if<ImagePtr>(&value); im && *im)
    s = raster((*im)->domain, "pixels") + ", " +
        count(static_cast<std::size_t>((*im)->channels), "channel", "channels");
  else if (auto* m = std::get_if<PolygonMapPtr>(&value); m && *m) {
    const glm::dvec2 extent = (*m)->max_corner - (*m)->min_corner;
    s = "polygon map: " + count((*m)->cells.size(), "cell", "cells") + ", " +
        count((*m)->edges.size(), "edge", "edges") + " over " + metres(extent.x) + " x " + metres(extent.y);
  } else if (auto* p = std::get_if<PointsPtr>(&value); p && *p)
    s = count((*p)->size(), "point", "points");
  else if (auto* c = std::get_if<CurvesPtr>(&value); c && *c)
    s = count((*c)->size(), "curve", "curves") + ", " + count((*c)->vertex_count(), "vertex", "vertices");
  else if (auto* sc = std::get_if<ScenePtr>(&value); sc && *sc)
    s = count((*sc)->size(), "instance", "instances");
  if (backdrop) s += (s.empty() ? "" : " on ") + raster(backdrop->domain, "samples");
  return s;
}

}  // namespace orogen::editor
