// Preview rendering on the CPU: colour maps, hillshade orientation, image encoding, the terrain mesh and
// the orbit camera.
#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>

#include "editor/model/orbit_camera.h"
#include "editor/model/preview_image.h"
#include "editor/model/scene_preview.h"
#include "editor/model/terrain_mesh.h"
#include "graph/graph.h"
#include "graph/polygon_map.h"
#include "nodes/common/categorical_palette.h"

#include <algorithm>
#include <cmath>

namespace orogen::editor {
namespace {

Heightfield ramp_x(int n, float slope) {
  Heightfield h(Domain::from_extent({0, 0}, {100, 100}, {n, n}));
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) h.at(i, j) = slope * static_cast<float>(h.domain.x(i));
  return h;
}

TEST(PreviewLabel, APolygonMapIsDescribedByItsCellsAndExtentNotAsARaster) {
  // The 2D preview frames a polygon map by its rectangle; the label said "2 x 2 samples, spacing 4.1e+03 m".
  auto map = std::make_shared<PolygonMap>();
  map->min_corner = {0, 0};
  map->max_corner = {4096, 4096};
  map->cells.resize(3);
  map->edges.resize(7);
  const std::string label = describe_preview_value(PolygonMapPtr(map));
  EXPECT_EQ(label, "polygon map: 3 cells, 7 edges over 4096 m x 4096 m");

  const auto field = std::make_shared<Heightfield>(Domain::from_extent({0, 0}, {4096, 4096}, {257, 257}));
  EXPECT_EQ(describe_preview_value(HeightfieldPtr(field)), "257 x 257 samples, spacing 16 m");
  const auto odd = std::make_shared<Heightfield>(Domain::from_extent({0, 0}, {4096, 4096}, {256, 256}));
  EXPECT_EQ(describe_preview_value(HeightfieldPtr(odd)), "256 x 256 samples, spacing 16.06 m");
  // Over a terrain: the map is still cells; the raster is the terrain's.
  EXPECT_EQ(describe_preview_value(PolygonMapPtr(map), field.get()),
            "polygon map: 3 cells, 7 edges over 4096 m x 4096 m on 257 x 257 samples, spacing 16 m");
  auto points = std::make_shared<Points>();
  points->position.resize(1);
  EXPECT_EQ(describe_preview_value(PointsPtr(points)), "1 point");
}

TEST(ColorMap, EndpointsAndClamping) {
  EXPECT_EQ(colormap(ColorMap::Gray, 0.0), glm::vec3(0.0f));
  EXPECT_EQ(colormap(ColorMap::Gray, 1.0), glm::vec3(1.0f));
  EXPECT_EQ(colormap(ColorMap::Gray, 7.0), glm::vec3(1.0f));
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
  const auto px = render_heightfield(h, {ColorMap::Gray, false, {}});
  ASSERT_EQ(px.rgba.size(), 64u);
  EXPECT_EQ(px.rgba[0], 255) << "top row shows the highest y (value 3 = white)";
  EXPECT_EQ(px.rgba[(3 * 4) * 4], 0) << "bottom row shows y = 0";
}

TEST(RenderPoints, DotsInTheirClassColourWithWorldYUpAndAspectKept) {
  const Domain d = Domain::from_extent({100, 0}, {200, 100}, {64, 32});
  Points pts;
  pts.add({101, 99, 0}, 0);   // top-left corner
  pts.add({299, 1, 0}, 2);    // bottom-right corner
  pts.add({5000, 50, 0}, 1);  // outside: clipped
  const PreviewPixels px = render_points(pts, d, 128);
  ASSERT_EQ(px.width, 128);
  ASSERT_EQ(px.height, 64);
  auto at = [&](int i, int j) { return &px.rgba[(static_cast<std::size_t>(j) * px.width + i) * 4]; };
  const glm::vec4 c0 = marker_color(0), c2 = marker_color(2);
  EXPECT_EQ(at(0, 0)[0], static_cast<int>(std::lround(c0.r * 255)));
  EXPECT_EQ(at(0, 0)[1], static_cast<int>(std::lround(c0.g * 255)));
  EXPECT_EQ(at(127, 63)[2], static_cast<int>(std::lround(c2.b * 255)));
  EXPECT_EQ(at(64, 32)[0], at(64, 0)[0]) << "background elsewhere";
  int coloured = 0;
  for (int j = 0; j < px.height; ++j)
    for (int i = 0; i < px.width; ++i) coloured += at(i, j)[0] != at(64, 32)[0];
  EXPECT_GT(coloured, 1);
  EXPECT_LE(coloured, 8) << "two sparse dots of 2 x 2 pixels at most";
}

TEST(RenderCurves, LinesAsWideAsTheCurve) {
  const Domain d = Domain::from_extent({0, 0}, {128, 128}, {64, 64});  // 1 pixel per metre at 128
  Curves cs;
  Curve narrow, wide;
  narrow.points = {{0, 96, 0}, {128, 96, 0}};
  narrow.width = {1, 1};
  wide.points = {{0, 32, 0}, {128, 32, 0}};
  wide.width = {9, 9};
  cs.curves = {narrow, wide};
  const PreviewPixels px = render_curves(cs, d, 128);
  ASSERT_EQ(px.width, 128);
  auto column_cover = [&](int i, int j0, int j1) {
    int n = 0;
    for (int j = j0; j < j1; ++j) n += px.rgba[(static_cast<std::size_t>(j) * px.width + i) * 4 + 2] > 100;
    return n;
  };
  // World y = 96 is pixel row 32 (y up), y = 32 is row 96.
  EXPECT_NEAR(column_cover(64, 0, 64), 1, 1);
  EXPECT_NEAR(column_cover(64, 64, 128), 9, 1);
  const std::uint8_t* n = &px.rgba[(32 * 128 + 64) * 4];
  const std::uint8_t* w = &px.rgba[(96 * 128 + 64) * 4];
  EXPECT_GT(n[0], w[0]) << "the widest curve is the deepest blue";
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
  TerrainMeshOptions options;
  options.max_side = 200;
  const auto mesh = build_terrain_mesh(h, options);
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

// --- Output kinds choose the colour map --------------------------------------------------------------------

NodeType kind_type(std::string name, std::vector<PortDecl> inputs, std::vector<PortDecl> outputs) {
  NodeType t;
  t.name = std::move(name);
  t.inputs = std::move(inputs);
  t.outputs = std::move(outputs);
  t.execute = [](ExecContext&) {};
  return t;
}

TEST(OutputKind, DeclaredInferredFromNameAndPassedThroughOperators) {
  PortDecl hf_out{"out", PortType::Heightfield, "", false, OutputKind::Auto};
  PortDecl hf_in{"in", PortType::Heightfield, "", false, OutputKind::Auto};
  const NodeType gen = kind_type("Gen", {}, {hf_out});
  PortDecl signed_out = hf_out;
  signed_out.kind = OutputKind::Signed;
  const NodeType curv = kind_type(
      "Curv", {hf_in}, {signed_out, PortDecl{"band_mask", PortType::Heightfield, "", false, OutputKind::Auto}});
  const NodeType op = kind_type("Op", {hf_in}, {hf_out});
  PortDecl a = hf_in, b = hf_in;
  a.name = "a";
  b.name = "b";
  const NodeType bin = kind_type("Bin", {a, b}, {hf_out});
  Graph g;
  g.add_node(gen, "gen");
  g.add_node(curv, "curv");
  g.add_node(op, "op");
  g.add_node(op, "op2");
  g.add_node(bin, "bin");
  g.connect({"gen", "out"}, "curv", "in");
  g.connect({"curv", "out"}, "op", "in");
  g.connect({"curv", "band_mask"}, "bin", "a");
  g.connect({"op", "out"}, "bin", "b");
  EXPECT_EQ(resolve_output_kind(g, "gen", "out"), OutputKind::Height);       // a generator: a height
  EXPECT_EQ(resolve_output_kind(g, "curv", "out"), OutputKind::Signed);      // declared
  EXPECT_EQ(resolve_output_kind(g, "curv", "band_mask"), OutputKind::Mask);  // named like a mask
  EXPECT_EQ(resolve_output_kind(g, "op", "out"), OutputKind::Signed);        // passes on its input's kind
  EXPECT_EQ(resolve_output_kind(g, "bin", "out"), OutputKind::Mask);         // a binary op: input a
  EXPECT_EQ(resolve_output_kind(g, "op2", "out"), OutputKind::Height);       // unconnected
  EXPECT_EQ(resolve_output_kind(g, "nope", "out"), OutputKind::Height);
}

TEST(OutputKind, StylePerKind) {
  EXPECT_EQ(style_for(OutputKind::Height).map, ColorMap::Terrain);
  EXPECT_TRUE(style_for(OutputKind::Height).hillshade);
  const auto mask = style_for(OutputKind::Mask);
  EXPECT_EQ(mask.map, ColorMap::Gray);
  ASSERT_TRUE(mask.range.has_value());
  EXPECT_EQ(mask.range->lo, 0.0f);
  EXPECT_EQ(mask.range->hi, 1.0f);
  EXPECT_EQ(style_for(OutputKind::Signed).map, ColorMap::Diverging);
  EXPECT_EQ(style_for(OutputKind::WaterDepth).map, ColorMap::Water);

  // A mask of 0.5 everywhere is mid-gray (not stretched to its own range); a signed field puts 0 in the
  // middle of the diverging map (white) whatever its asymmetry.
  Heightfield half(Domain::from_extent({0, 0}, {10, 10}, {4, 4}));
  std::fill(half.data.begin(), half.data.end(), 0.5f);
  const auto px = render_heightfield(half, mask);
  EXPECT_NEAR(px.rgba[0], 128, 1);
  Heightfield s(Domain::from_extent({0, 0}, {10, 10}, {4, 1}));
  s.data = {-1.0f, 0.0f, 3.0f, 0.5f};
  const auto r = style_range(s, style_for(OutputKind::Signed));
  EXPECT_EQ(r.lo, -3.0f);
  EXPECT_EQ(r.hi, 3.0f);
  const auto spx = render_heightfield(s, style_for(OutputKind::Signed));
  EXPECT_GT(spx.rgba[4 + 0], 240);  // 0: white
  EXPECT_GT(spx.rgba[4 + 2], 240);
  EXPECT_GT(spx.rgba[0 + 2], spx.rgba[0 + 0]);  // negative: blue
  EXPECT_GT(spx.rgba[8 + 0], spx.rgba[8 + 2]);  // positive: red
}

// --- Lakes and rivers in 3D --------------------------------------------------------------------------------

TEST(WaterMesh, FlatSurfaceAtTerrainPlusDepthOnlyOverWater) {
  // A bowl with a lake filled to level 5 in its middle.
  const int n = 32;
  Heightfield terrain(Domain::from_extent({0, 0}, {310, 310}, {n, n}));
  Heightfield depth(terrain.domain);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double r = std::hypot(i - 15.5, j - 15.5);
      terrain.at(i, j) = static_cast<float>(r);
      depth.at(i, j) = r < 5.0 ? static_cast<float>(5.0 - r) : 0.0f;
    }
  const TerrainMesh water = build_water_mesh(terrain, depth);
  ASSERT_FALSE(water.indices.empty());
  for (const auto& p : water.positions) {
    EXPECT_NEAR(p.z, 5.0f, 1e-4f);                                     // flat, at the water level (shore vertices too)
    EXPECT_LT(std::hypot(p.x / 10.0 - 15.5, p.y / 10.0 - 15.5), 7.5);  // only around the lake
  }
  for (const auto& c : water.colors) EXPECT_LT(c.a, 1.0f);  // translucent
  // Nothing wet: nothing drawn.
  std::fill(depth.data.begin(), depth.data.end(), 0.0f);
  EXPECT_TRUE(build_water_mesh(terrain, depth).indices.empty());
}

TEST(WaterOverTerrain, DryIsTheTerrainWetIsBlue) {
  Heightfield terrain = ramp_x(16, 1.0f);
  Heightfield depth(terrain.domain);
  depth.at(3, 5) = 2.0f;
  const auto plain = render_heightfield(terrain, style_for(OutputKind::Height));
  const auto px = render_water_over_terrain(terrain, depth);
  ASSERT_EQ(px.rgba.size(), plain.rgba.size());
  const std::size_t wet = (static_cast<std::size_t>(15 - 5) * 16 + 3) * 4;  // row 5 from the bottom
  for (std::size_t k = 0; k < px.rgba.size(); k += 4) {
    if (k == wet) continue;
    for (int c = 0; c < 4; ++c) EXPECT_EQ(px.rgba[k + c], plain.rgba[k + c]) << k;
  }
  EXPECT_GT(px.rgba[wet + 2], px.rgba[wet + 0]);  // blue
  EXPECT_NE(px.rgba[wet + 2], plain.rgba[wet + 2]);
}

TEST(CurveRibbons, WidthAwareAndOnTheTerrain) {
  Curves curves;
  Curve c;
  c.points = {{0, 50, 1}, {50, 50, 1}, {100, 50, 1}};
  c.width = {4, 8, 12};
  curves.curves.push_back(c);
  Heightfield ground(Domain::from_extent({0, 0}, {100, 100}, {11, 11}));
  std::fill(ground.data.begin(), ground.data.end(), 3.0f);  // above the curve's own height
  const TerrainMesh m = build_curve_ribbons(curves, &ground, {.min_width = 6.0f, .lift = 0.5f});
  ASSERT_EQ(m.positions.size(), 6u);
  ASSERT_EQ(m.indices.size(), 12u);
  // Across the flow (y), as wide as the curve (at least min_width).
  EXPECT_NEAR(m.positions[1].y - m.positions[0].y, 6.0f, 1e-4f);
  EXPECT_NEAR(m.positions[3].y - m.positions[2].y, 8.0f, 1e-4f);
  EXPECT_NEAR(m.positions[5].y - m.positions[4].y, 12.0f, 1e-4f);
  for (const auto& p : m.positions) EXPECT_NEAR(p.z, 3.5f, 1e-4f);  // on the terrain, lifted
  // Wider is deeper blue.
  EXPECT_LT(m.colors[4].r, m.colors[0].r);
  // Without terrain: at the curve's height.
  const TerrainMesh bare = build_curve_ribbons(curves, nullptr, {});
  for (const auto& p : bare.positions) EXPECT_NEAR(p.z, 1.0f, 1e-4f);
}

TEST(Preview, CategoricalIdsAndImageChannels) {
  // Ids by their rounded value, not their place in the range: id 2 looks the same in any field.
  Heightfield ids(Domain::from_extent({0, 0}, {3, 0}, {4, 1}));
  ids.data = {0.0f, 1.0f, 2.0f, 13.0f};
  const auto px = render_heightfield(ids, {ColorMap::Categorical, false, {}});
  auto rgb = [&](int i) {
    return glm::vec3(px.rgba[std::size_t(i) * 4], px.rgba[std::size_t(i) * 4 + 1], px.rgba[std::size_t(i) * 4 + 2]) /
           255.0f;
  };
  for (int i = 0; i < 3; ++i) EXPECT_LT(glm::length(rgb(i) - categorical_srgb(i)), 0.01f) << i;
  EXPECT_LT(glm::length(rgb(3) - categorical_srgb(13)), 0.01f) << "ids past the palette keep their own color";
  EXPECT_GT(glm::length(categorical_srgb(13) - categorical_srgb(1)), 0.1f) << "13 does not repeat 1";
  EXPECT_GT(glm::length(categorical_srgb(0) - categorical_srgb(1)), 0.2f);
  // A 12-channel image: one channel as a field.
  Image img(Domain::from_extent({0, 0}, {1, 1}, {2, 2}), 12);
  for (std::size_t q = 0; q < img.data.size(); ++q) img.data[q] = static_cast<float>(q);
  const Heightfield jun = image_channel(img, 5);
  EXPECT_EQ(jun.data, (std::vector<float>{5.0f, 17.0f, 29.0f, 41.0f}));
  EXPECT_EQ(image_channel(img, 12).data, std::vector<float>(4, 0.0f)) << "out of range: zeros";
}

}  // namespace
}  // namespace orogen::editor
