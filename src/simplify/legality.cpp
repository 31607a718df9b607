#include "legality.h"

#include <algorithm>

namespace dynpm::simplification {

bool second_order_neighbours_ok(const CollapseMesh& mesh, uint32_t v0, uint32_t v1,
                                std::span<const uint32_t> edge_faces, VertexMarks& marks) {
  // Mark v1's second-order neighbours, then the corners of the edge's faces with another
  // stamp; no corner of v0's faces may still carry the first.
  const uint32_t in_v1_ring = marks.stamp += 2, in_edge_face = in_v1_ring + 1;
  for (uint32_t f : mesh.faces_of(v1))
    for (uint32_t z : mesh.face(f).v)
      if (z != kNoVertex) marks.mark[z] = in_v1_ring;
  for (uint32_t f : edge_faces)
    for (uint32_t z : mesh.face(f).v)
      if (z != kNoVertex) marks.mark[z] = in_edge_face;
  for (uint32_t f : mesh.faces_of(v0))
    for (uint32_t z : mesh.face(f).v)
      if (z != kNoVertex && z != v0 && z != v1 && marks.mark[z] == in_v1_ring) return false;
  return true;
}

bool first_order_neighbours_ok(const CollapseMesh& mesh, uint32_t v0, uint32_t v1) {
  std::vector<uint32_t> n0, n1;
  mesh.neighbours(v0, n0);
  mesh.neighbours(v1, n1);
  for (uint32_t z : n0) {
    if (z == v1 || std::find(n1.begin(), n1.end(), z) == n1.end()) continue;
    bool shared = false;
    for (uint32_t f : mesh.faces_of(v0)) {
      const Face& face = mesh.face(f);
      shared |= face.contains(v1) && face.contains(z);
    }
    if (!shared) return false;
  }
  return true;
}

}  // namespace dynpm::simplification
