// Preview rendering on the CPU: colour maps, hillshade orientation, image encoding, the terrain mesh and
// the orbit camera.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include "editor/model/orbit_camera.h"
#include "editor/model/preview_image.h"
#include "editor/model/terrain_mesh.h"

namespace orogen::editor {
namespace {

Heightfield ramp_x(int n, float slope) {
  Heightfield h(Domain::from_extent({0, 0}, {100, 100}, {n, n}));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) h.at(i, j) = slope * static_cast<float>(h.domain.x(i));
  return h;
}

TEST(ColorMap, EndpointsAndClamping) {
  EXPECT_EQ(colormap(ColorMap::Grey, 0.0), glm::vec3(0.0f));
  EXPECT_EQ(colormap(ColorMap::Grey, 1.0), glm::vec3(1.0f));
  EXPECT_EQ(colormap(ColorMap::Grey, 7.0), glm::vec3(1.0f));
  const glm::vec3 v0 = colormap(ColorMap::Viridis, 0.0), v1 = colormap(ColorMap::Viridis, 1.0);
  EXPECT_GT(v0.b, v0.g);  // viridis starts purple
  EXPECT_GT(v1.r, 0.9f);  // and ends yellow
  EXPECT_GT(v1.g, 0.8f);
  // Terrain: water blue at the bottom, snow white at the top.
  EXPECT_GT(colormap(ColorMap::Terrain, 0.05).b, colormap(ColorMap::Terrain, 0.05).r);
  EXPECT_GT(colormap(ColorMap::Terrain, 1.0).r, 0.95f);
}

TEST(ColorMap, ViridisLuminanceIncreases) {
  float prev = -1.0f;
  for (int k = 0; k <= 20; ++k) {
    const glm::vec3 c = colormap(ColorMap::Viridis, k / 20.0);
    const float y = 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
    EXPECT_GT(y, prev) << k;
    prev = y;
  }
}

TEST(Hillshade, FlatIsSinAltitudeAndSlopesFacingTheLightAreBrighter) {
  const auto flat = hillshade(ramp_x(16, 0.0f), 315, 45);
  for (float v : flat) EXPECT_NEAR(v, std::sin(M_PI / 4), 1e-6);
  // Rising towards +x faces west; the default light comes from the north-west.
  const auto west = hillshade(ramp_x(16, 0.5f), 315, 45);
  const auto east = hillshade(ramp_x(16, -0.5f), 315, 45);
  EXPECT_GT(west[8 * 16 + 8], flat[0]);
  EXPECT_LT(east[8 * 16 + 8], flat[0]);
}

TEST(RenderHeightfield, RowsFlippedSoWorldYPointsUp) {
  Heightfield h(Domain::from_extent({0, 0}, {10, 10}, {4, 4}));
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) h.at(i, j) = static_cast<float>(j);
  const auto px = render_heightfield(h, {ColorMap::Grey, false, {}});
  ASSERT_EQ(px.rgba.size(), 64u);
  EXPECT_EQ(px.rgba[0], 255) << "top row shows the highest y (value 3 = white)";
  EXPECT_EQ(px.rgba[(3 * 4) * 4], 0) << "bottom row shows y = 0";
}

TEST(RenderImage, LinearToSrgb) {
  Image img(Domain::from_extent({0, 0}, {1, 1}, {2, 2}), 3, 0.0f);
  img.pixel(0, 0)[0] = 0.5f;  // linear 0.5 -> sRGB 188
  img.pixel(0, 0)[1] = 1.0f;
  const auto px = render_image(img);
  const std::uint8_t* p = &px.rgba[(1 * 2 + 0) * 4];  // sample (0, 0) is in the bottom row
  EXPECT_EQ(p[0], 188);
  EXPECT_EQ(p[1], 255);
  EXPECT_EQ(p[2], 0);
  EXPECT_EQ(p[3], 255);
}

TEST(TerrainMesh, GridDecimationNormalsAndWinding) {
  const auto h = ramp_x(1001, 0.25f);
  const auto mesh = build_terrain_mesh(h, {.max_side = 200});
  EXPECT_LE(mesh.columns, 200);
  EXPECT_GE(mesh.columns, 100);
  EXPECT_EQ(mesh.positions.size(), static_cast<std::size_t>(mesh.columns) * mesh.rows);
  EXPECT_EQ(mesh.indices.size(), static_cast<std::size_t>(mesh.columns - 1) * (mesh.rows - 1) * 6);
  EXPECT_FLOAT_EQ(mesh.max.x, 100.0f) << "the last sample is always included";
  EXPECT_FLOAT_EQ(mesh.max.z, 25.0f);
  const glm::vec3 expected = glm::normalize(glm::vec3(-0.25f, 0.0f, 1.0f));
  for (const auto& n : mesh.normals) EXPECT_NEAR(glm::dot(n, expected), 1.0f, 1e-5f);
  // Triangles face up (+z) like the surface.
  for (std::size_t t = 0; t < mesh.indices.size(); t += 3 * 97) {
    const auto a = mesh.positions[mesh.indices[t]], b = mesh.positions[mesh.indices[t + 1]],
               c = mesh.positions[mesh.indices[t + 2]];
    EXPECT_GT(glm::cross(b - a, c - a).z, 0.0f);
  }
}

TEST(OrbitCamera, OrbitKeepsDistanceAndFrameShowsTheBox) {
  OrbitCamera cam;
  for (double aspect : {1.0, 1.6}) {
    cam.frame({0, 0, 0}, {1000, 500, 200}, aspect);
    const glm::mat4 mvp = cam.projection(aspect) * cam.view();
    float widest = 0.0f;
    for (int k = 0; k < 8; ++k) {
      const glm::vec4 corner((k & 1) ? 1000 : 0, (k & 2) ? 500 : 0, (k & 4) ? 200 : 0, 1);
      const glm::vec4 clip = mvp * corner;
      EXPECT_GT(clip.w, 0.0f);
      EXPECT_LE(std::abs(clip.x / clip.w), 1.0f) << k;
      EXPECT_LE(std::abs(clip.y / clip.w), 1.0f) << k;
      widest = std::max({widest, std::abs(clip.x / clip.w), std::abs(clip.y / clip.w)});
    }
    EXPECT_GT(widest, 0.85f) << "framing is tight, not a distant speck";
  }
  const double d = cam.distance;
  cam.orbit({120, -40});
  EXPECT_NEAR(glm::length(cam.eye() - cam.target), d, 1e-6 * d);
  const glm::dvec3 t0 = cam.target;
  cam.pan({100, 0}, 500);
  EXPECT_GT(glm::length(cam.target - t0), 0.0);
  EXPECT_NEAR(cam.target.z, t0.z, 1e-9 + std::abs(cam.target.x - t0.x));  // moved mostly sideways
  cam.zoom(2);
  EXPECT_LT(cam.distance, d);
}

}  // namespace
}  // namespace orogen::editor
