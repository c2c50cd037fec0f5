#include "graph/mesh.h"

namespace orogen {

std::size_t Mesh::byte_size() const {
  // Points, normals, colours per vertex; connectivity per halfedge, edge and face.
  return sizeof(*this) + mesh.n_vertices() * (3 * sizeof(OpenMesh::Vec3f) + sizeof(OpenMesh::Vec4f)) +
         mesh.n_halfedges() * 4 * sizeof(int) + mesh.n_faces() * (sizeof(int) + sizeof(OpenMesh::Vec3f)) +
         mesh.n_edges() * sizeof(int);
}

}  // namespace orogen
