// An OpenMesh triangle mesh as the OBJ writer's arrays (obj_io.h), for the OpenMesh drivers.
#pragma once

#include <cstdint>
#include <vector>

#include "obj_io.h"

namespace peers {

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
