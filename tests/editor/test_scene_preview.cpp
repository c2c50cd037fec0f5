// The populated-scene preview on the CPU: finding the sources of a scene writer and of a scene maker
// (Instance), assembling its values from a preview, the per-class instance transforms, mesh geometry, and (end
// to end through the evaluation controller) instances standing on the terrain they were projected onto.
#include <cmath>

#include <gtest/gtest.h>

#include <glm/gtc/quaternion.hpp>

#include "editor/model/evaluation_controller.h"
#include "editor/model/scene_preview.h"
#include "graph/points.h"
#include "graph/scene.h"

namespace orogen::editor {
namespace {

// fbm (FBM) -> terrain (HeightfieldToMesh) -> write.terrain
// scatter (PoissonDisk) -> placed (ProjectToTerrain, height = fbm) -> scene (Instance) -> write.in
Graph scene_graph(bool with_terrain_mesh) {
  Graph g;
  g.domain.size = {256, 256};
  g.domain.resolution = {64, 64};
  g.add_node("FBM", "fbm");
  g.set_param("fbm", "feature_size", 120.0);
  g.set_param("fbm", "amplitude", 30.0);
  g.add_node("PoissonDisk", "scatter");
  g.set_param("scatter", "class_count", std::int64_t{2});
  g.set_param("scatter", "radius_0", 12.0);
  g.set_param("scatter", "radius_1", 16.0);
  g.add_node("ProjectToTerrain", "placed");
  g.connect({"scatter", "out"}, "placed", "in");
  g.connect({"fbm", "out"}, "placed", "height");
  g.add_node("Instance", "scene");
  g.set_param("scene", "missing_mesh", std::string("proxy"));
  g.connect({"placed", "out"}, "scene", "in");
  g.add_node("WriteScene", "write");
  g.connect({"scene", "out"}, "write", "in");
  if (with_terrain_mesh) {
    g.add_node("HeightfieldToMesh", "terrain");
    g.connect({"fbm", "out"}, "terrain", "in");
    g.connect({"terrain", "out"}, "write", "terrain");
    g.connect({"terrain", "out"}, "scene", "mesh_1");  // any mesh will do
  }
  return g;
}

TEST(ScenePreview, SourcesOfAWriterAndOfAnInstance) {
  const Graph g = scene_graph(true);
  EXPECT_TRUE(is_scene_writer(g.at("write")));
  EXPECT_FALSE(is_scene_writer(g.at("scene")));
  EXPECT_FALSE(is_scene_writer(g.at("placed")));
  EXPECT_EQ(scene_output(g.at("scene")), 0);
  EXPECT_EQ(scene_output(g.at("placed")), -1);
  EXPECT_FALSE(scene_sources(g, "placed").has_value());
  const auto s = scene_sources(g, "write");
  ASSERT_TRUE(s.has_value());
  EXPECT_TRUE(s->writer);
  EXPECT_EQ(s->scene, (PortRef{"scene", "out"}));
  EXPECT_EQ(s->terrain, (PortRef{"terrain", "out"}));
  EXPECT_EQ(s->ground, (PortRef{"fbm", "out"})) << "ProjectToTerrain's height, through the Instance";
  EXPECT_EQ(s->nodes(), (std::vector<std::string>{"scene", "terrain", "fbm"}));
  // The Instance node shows its own scene on the same ground, without a terrain mesh.
  const auto i = scene_sources(g, "scene");
  ASSERT_TRUE(i.has_value());
  EXPECT_FALSE(i->writer);
  EXPECT_EQ(i->scene, (PortRef{"scene", "out"}));
  EXPECT_TRUE(i->terrain.node.empty());
  EXPECT_EQ(i->ground, (PortRef{"fbm", "out"}));
  EXPECT_EQ(i->nodes(), (std::vector<std::string>{"scene", "fbm"}));
}

TEST(ScenePreview, GroundIsNeverAMaskOrDensity) {
  Graph g = scene_graph(false);
  // PoissonDisk straight into the Instance, with a density but no height: no ground.
  // A height feeding the density input is still not the ground.
  g.connect({"fbm", "out"}, "scatter", "density");
  g.connect({"scatter", "out"}, "scene", "in");
  auto s = scene_sources(g, "write");
  ASSERT_TRUE(s.has_value());
  EXPECT_TRUE(s->ground.node.empty()) << s->ground.str();
  // Its `height` input is taken.
  g.connect({"fbm", "out"}, "scatter", "height");
  s = scene_sources(g, "write");
  EXPECT_EQ(s->ground, (PortRef{"fbm", "out"}));
}

TEST(ScenePreview, InstanceTransformsTranslateRotateScale) {
  Points p;
  p.add({10, 20, 5}, 1);
  p.rotation[0] = glm::angleAxis(static_cast<float>(M_PI / 2), glm::vec3(0, 0, 1));
  p.scale[0] = {2, 2, 3};
  p.add({1, 2, 3}, 0);
  p.add({4, 5, 6}, 7);   // no mesh for class 7
  p.add({7, 8, 9}, -1);  // out of range
  p.add({0, 0, 0}, 1);
  const SceneInstances inst = build_instances(p, {true, true, false});
  ASSERT_EQ(inst.per_class.size(), 3u);
  EXPECT_EQ(inst.count, 3u);
  EXPECT_EQ(inst.skipped, 2u);
  ASSERT_EQ(inst.per_class[1].size(), 2u);
  ASSERT_EQ(inst.per_class[0].size(), 1u);
  const glm::mat4& m = inst.per_class[1][0];
  // Local x (scaled by 2) turns to world +y; local z (the up axis) is scaled by 3; the origin goes to the point.
  const glm::vec3 x(m * glm::vec4(1, 0, 0, 1)), z(m * glm::vec4(0, 0, 1, 1)), o(m * glm::vec4(0, 0, 0, 1));
  EXPECT_NEAR(x.x, 10.0f, 1e-5);
  EXPECT_NEAR(x.y, 22.0f, 1e-5);
  EXPECT_NEAR(x.z, 5.0f, 1e-5);
  EXPECT_NEAR(z.z, 8.0f, 1e-5);
  EXPECT_EQ(o, glm::vec3(10, 20, 5));
  EXPECT_EQ(glm::vec3(inst.per_class[0][0][3]), glm::vec3(1, 2, 3));
  // A proxy's box, transformed: the base stays at the point, the top at 3 m (scale z) above it.
  const TerrainMesh proxy = proxy_geometry(class_color(1));
  glm::vec3 lo, hi;
  SceneInstances one;
  one.per_class = {{}, {m}};
  ASSERT_TRUE(instance_bounds(one, {nullptr, &proxy}, lo, hi));
  EXPECT_NEAR(lo.z, 5.0f, 1e-5);
  EXPECT_NEAR(hi.z, 8.0f, 1e-5);
  EXPECT_NEAR(hi.x - lo.x, 2.0f, 1e-5);
  EXPECT_FALSE(instance_bounds(SceneInstances{}, {}, lo, hi));
}

TEST(ScenePreview, ProxyIsClosedAndFacesOutward) {
  const TerrainMesh t = proxy_geometry({1, 0, 0, 1});
  ASSERT_EQ(t.indices.size(), 24u);
  for (std::size_t f = 0; f < 8; ++f) {
    const glm::vec3 a = t.positions[t.indices[3 * f]], b = t.positions[t.indices[3 * f + 1]],
                    c = t.positions[t.indices[3 * f + 2]];
    const glm::vec3 centre = (a + b + c) / 3.0f - glm::vec3(0, 0, 0.5f);
    EXPECT_GT(glm::dot(glm::cross(b - a, c - a), centre), 0.0f) << f;
  }
  EXPECT_EQ(t.min, glm::vec3(-0.5f, -0.5f, 0.0f));
  EXPECT_EQ(t.max, glm::vec3(0.5f, 0.5f, 1.0f));
}

TEST(ScenePreview, MeshGeometryConvertsColorsAndTintsUniformMeshes) {
  Mesh m;
  auto& t = m.mesh;
  const auto a = t.add_vertex({0, 0, 0}), b = t.add_vertex({1, 0, 0}), c = t.add_vertex({1, 1, 10}),
             d = t.add_vertex({0, 1, 10});
  t.add_face(std::vector<TriMesh::VertexHandle>{a, b, c, d});  // a quad: split in two triangles
  t.update_normals();
  for (auto v : t.vertices()) t.set_color(v, OpenMesh::Vec4f(0.5f, 1.0f, 0.0f, 1.0f));
  const TerrainMesh g = mesh_geometry(m);
  EXPECT_EQ(g.indices.size(), 6u);
  EXPECT_NEAR(g.colors[0].r, 188.0f / 255.0f, 0.003f) << "linear 0.5 is sRGB 188";
  EXPECT_EQ(g.min, glm::vec3(0, 0, 0));
  EXPECT_EQ(g.max, glm::vec3(1, 1, 10));
  const TerrainMesh tinted = mesh_geometry(m, {true});
  EXPECT_EQ(glm::vec3(tinted.colors[0]), colormap(ColorMap::Terrain, 0.0));
  EXPECT_EQ(glm::vec3(tinted.colors[2]), colormap(ColorMap::Terrain, 1.0));
  t.set_color(a, OpenMesh::Vec4f(0, 0, 0, 1));  // not uniform: its colours are kept
  EXPECT_NEAR(mesh_geometry(m, {true}).colors[2].r, 188.0f / 255.0f, 0.003f);
}

// Through the editor's evaluation path: the sources evaluated at preview resolution, the scene assembled,
// and every instance's base on the ground under it (ProjectToTerrain, bilinear).
TEST(ScenePreview, InstancesStandOnTheTerrainTheyWereProjectedOnto) {
  const Graph g = scene_graph(true);
  const auto sources = scene_sources(g, "write");
  ASSERT_TRUE(sources.has_value());
  EvaluationController ec;
  ec.request_preview(g, sources->nodes(), 1);
  ec.wait_idle();
  const auto result = ec.preview();
  ASSERT_TRUE(result);
  const ScenePreview scene = assemble_scene(g, *sources, result->outputs);
  ASSERT_TRUE(scene.scene);
  ASSERT_TRUE(scene.points);
  ASSERT_TRUE(scene.terrain);
  ASSERT_TRUE(scene.ground);
  ASSERT_EQ(scene.scene->classes.size(), 2u);
  EXPECT_TRUE(scene.scene->classes.at(0).proxy);
  EXPECT_EQ(scene.scene->classes.at(1).mesh, scene.terrain);
  ASSERT_GT(scene.points->size(), 50u);
  const SceneClassInstances inst = build_instances(*scene.scene);
  EXPECT_EQ(inst.class_ids, (std::vector<std::int32_t>{0, 1}));
  EXPECT_EQ(inst.count, scene.points->size());
  EXPECT_EQ(inst.skipped, 0u);
  for (std::size_t c = 0; c < 2; ++c) EXPECT_FALSE(inst.per_class[c].empty()) << c;
  const TerrainMesh terrain = mesh_geometry(*scene.terrain, {true});
  for (const auto& cls : inst.per_class)
    for (const glm::mat4& m : cls) {
      const glm::vec3 base(m[3]);
      const double ground = scene.ground->sample_world(base.x, base.y);
      ASSERT_NEAR(base.z, ground, 1e-3 * 30.0) << base.x << ", " << base.y;
      // And inside the terrain mesh's box.
      EXPECT_GE(base.z, terrain.min.z - 1e-3f);
      EXPECT_LE(base.z, terrain.max.z + 1e-3f);
    }
  // The terrain mesh is white (no colours input): tinted by height, so not uniform.
  EXPECT_NE(terrain.colors.front(), terrain.colors.back());
}

}  // namespace
}  // namespace orogen::editor
