#include "nodes/scatter/instance.h"

#include <set>
#include <string_view>

#include "nodes/common/text.h"

namespace orogen {

std::shared_ptr<Mesh> proxy_mesh() {
  auto out = std::make_shared<Mesh>();
  TriMesh& t = out->mesh;
  const TriMesh::VertexHandle v[6] = {t.add_vertex({0, 0, 0}),        t.add_vertex({0, 0, 1}),
                                      t.add_vertex({0.5f, 0, 0.5f}),  t.add_vertex({0, 0.5f, 0.5f}),
                                      t.add_vertex({-0.5f, 0, 0.5f}), t.add_vertex({0, -0.5f, 0.5f})};
  const int ring[4] = {2, 3, 4, 5};
  for (int k = 0; k < 4; ++k) {
    const auto a = v[ring[k]], b = v[ring[(k + 1) % 4]];
    t.add_face(v[1], a, b);
    t.add_face(v[0], b, a);
  }
  t.update_normals();
  for (auto vh : t.vertices()) t.set_color(vh, OpenMesh::Vec4f(0.6f, 0.6f, 0.6f, 1.0f));
  return out;
}

TableSchema class_name_schema() {
  TableSchema s;
  s.add("class", ColumnType::Integer)
      .range(0, 2147483647)
      .unit_of(Unit::Id)
      .describe("Class id of the points (0, 1, ...)");
  s.add("name", ColumnType::Text).describe("The class's name: its glTF nodes and meshes; empty: class_<id>");
  return s;
}

std::map<std::int32_t, std::string> class_names_from_table(const TableValue& table) {
  std::map<std::int32_t, std::string> out;
  for (const auto& row : table.rows) {
    const auto& name = std::get<std::string>(row[1]);
    if (!name.empty()) out[static_cast<std::int32_t>(std::get<std::int64_t>(row[0]))] = name;
  }
  return out;
}

Scene make_scene(std::shared_ptr<const Points> points, const std::map<std::int32_t, MeshPtr>& meshes,
                 const InstanceOptions& options) {
  if (!points) throw std::invalid_argument("no points to instance");
  try {
    points->check_consistent();
  } catch (const std::logic_error& e) {
    throw std::invalid_argument(e.what());
  }
  auto name_of = [&](std::int32_t cls) {
    const auto it = options.names.find(cls);
    return it != options.names.end() ? it->second : "class_" + std::to_string(cls);
  };
  Scene scene;
  for (const auto& [cls, mesh] : meshes)
    if (mesh) scene.classes[cls] = SceneClass{name_of(cls), mesh, false};
  // Classes with points but no mesh, with their point counts (in class order: the error names the first).
  std::map<std::int32_t, std::size_t> missing;
  for (const std::int32_t cls : points->class_id)
    if (!scene.classes.count(cls)) ++missing[cls];
  if (missing.empty() || options.missing != MissingMesh::Skip) scene.instances = points;
  if (missing.empty()) return scene;
  switch (options.missing) {
    case MissingMesh::Error: {
      const auto& [cls, count] = *missing.begin();
      throw std::invalid_argument("class " + std::to_string(cls) + " has " + std::to_string(count) +
                                  (count == 1 ? " point" : " points") + " but no mesh: connect mesh_" +
                                  std::to_string(cls) + ", or set missing_mesh to proxy or skip");
    }
    case MissingMesh::Proxy: {
      const MeshPtr proxy = proxy_mesh();
      for (const auto& [cls, count] : missing) scene.classes[cls] = SceneClass{name_of(cls), proxy, true};
      return scene;
    }
    case MissingMesh::Skip: {
      scene.instances =
          std::make_shared<Points>(points->subset([&](std::size_t i) { return !missing.count(points->class_id[i]); }));
      return scene;
    }
  }
  return scene;
}

}  // namespace orogen
