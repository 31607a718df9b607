// OpenMesh triangle meshes from and to the OBJ reader's and writer's arrays (obj_io.h), for the
// OpenMesh drivers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "obj_io.h"

namespace peers {

// The soup's vertices and faces added to `mesh`; returns how many faces OpenMesh refused
// (complex edges).
template <class Mesh>
std::size_t add_soup(Mesh& mesh, const TriSoup& in) {
  std::vector<typename Mesh::VertexHandle> vh;
  vh.reserve(in.V.size());
  for (const Vec3& p : in.V) vh.push_back(mesh.add_vertex(typename Mesh::Point(p[0], p[1], p[2])));
  std::size_t rejected = 0;
  for (const Tri& t : in.F)
    if (!mesh.add_face(vh[t[0]], vh[t[1]], vh[t[2]]).is_valid()) ++rejected;
  return rejected;
}

template <class Mesh>
void openmesh_arrays(const Mesh& mesh, std::vector<Vec3>& vertices, std::vector<Tri>& faces) {
  vertices.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    vertices.push_back({p[0], p[1], p[2]});
  }
  for (auto f : mesh.faces()) {
    Tri t{};
    int k = 0;
    for (auto v : mesh.fv_range(f)) t[k++] = static_cast<std::uint32_t>(v.idx());
    faces.push_back(t);
  }
}

}  // namespace peers
