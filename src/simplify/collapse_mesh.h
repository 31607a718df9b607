// The mesh being simplified: faces that change in place (a quad that loses a corner becomes a
// triangle with kNoVertex in slot 3; a vanished triangle gets kNoVertex in every slot) and, per
// vertex, the list of its live faces in one pooled array. Face ids stay the input's.
#pragma once

#include <span>
#include <vector>

#include "core/face_geometry.h"
#include "dynpm/simplify.h"

namespace dynpm::simplification {

class CollapseMesh {
 public:
  explicit CollapseMesh(const Topology& topology);

  uint32_t vertex_count() const { return static_cast<uint32_t>(list_start_.size()); }
  const Face& face(uint32_t f) const { return faces_[f]; }
  bool face_alive(uint32_t f) const { return faces_[f].v[0] != kNoVertex; }
  std::span<const uint32_t> faces_of(uint32_t v) const {
    return {pool_.data() + list_start_[v], list_size_[v]};
  }
  bool vertex_alive(uint32_t v) const { return list_size_[v] > 0; }
  uint32_t live_vertices() const { return live_vertices_; }
  size_t live_faces() const { return live_faces_; }

  // Vertices joined to v by an edge, and vertices sharing a face with v (second-order
  // neighbours, paper §2); each once, v excluded. `out` is cleared first.
  void neighbours(uint32_t v, std::vector<uint32_t>& out) const;
  void second_order_neighbours(uint32_t v, std::vector<uint32_t>& out) const;

  // Performs the half-edge collapse v0 → v1 (legality checked by the caller) and fills the
  // record's wings and moved faces (moved_faces points into `moved`).
  void collapse(uint32_t v0, uint32_t v1, CollapseRecord& record, std::vector<uint32_t>& moved);

  // The live mesh as a Topology: faces in input order, vertices renumbered in input order;
  // original_vertex maps new → input vertex.
  Topology to_topology(const Topology& input, std::vector<uint32_t>& original_vertex) const;

 private:
  void remove_face_from(uint32_t v, uint32_t f);
  void reserve_list(uint32_t v, uint32_t size);
  void compact_pool(uint32_t extra);

  std::vector<Face> faces_;
  std::vector<uint32_t> list_start_, list_size_, list_capacity_, pool_;
  uint32_t live_vertices_ = 0;
  size_t live_faces_ = 0;
};

}  // namespace dynpm::simplification
