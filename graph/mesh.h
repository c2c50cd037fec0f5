#pragma once
// A triangle mesh in world metres (z up) with per-vertex normals and linear RGBA colours:
// hull rocks, trees, terrain meshes. Wraps an OpenMesh TriMesh so the heavy OpenMesh headers are only
// included where meshes are built or written.
#include <cstddef>
#include <memory>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

namespace orogen {

struct MeshTraits : public OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3f;
  using Normal = OpenMesh::Vec3f;
  using Color = OpenMesh::Vec4f;
  VertexAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::Color | OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  HalfedgeAttributes(OpenMesh::Attributes::PrevHalfedge);
};

using TriMesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

struct Mesh {
  TriMesh mesh;

  std::size_t vertex_count() const { return mesh.n_vertices(); }
  std::size_t face_count() const { return mesh.n_faces(); }
  std::size_t byte_size() const;
};

using MeshPtr = std::shared_ptr<const Mesh>;

}  // namespace orogen
