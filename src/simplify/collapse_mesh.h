// The mesh being simplified: faces that change in place (a quad that loses a corner becomes a
// triangle with kNoVertex in slot 3; a vanished triangle gets kNoVertex in every slot) and, per
// vertex, the list of its live faces in a pooled array. Face ids stay the input's.
//
// Islands (docs/simplify.md "Islands"): sets of whole connected components whose collapses run on
// separate threads. Each keeps its vertices' face lists in a pool of its own and counts its live
// vertices and faces, so that a collapse writes nothing another island reads. Until
// split_into_islands() the whole mesh is one island.
#pragma once

#include <span>
#include <string>
#include <vector>

#include "core/face_geometry.h"
#include "dynpm/simplify.h"

namespace dynpm::simplification {

// What collapse() does to the faces alone, from its record: moved faces get v1 for v0, a wing
// quad loses v0, a wing triangle vanishes (islands.h replays a cut this way).
void collapse_faces(std::span<Face> faces, const CollapseRecord& record);

// The faces still alive (a first corner) as a Topology: faces in input order, the vertices in
// them renumbered in input order; original_vertex maps new → input vertex.
Topology live_topology(const Topology& input, std::span<const Face> faces,
                       std::vector<uint32_t>& original_vertex);

// Test mode (SimplifyOptions::check_every_collapse): `now` is valid ((M1)–(M3), no repeated
// vertex or duplicate face) and keeps the input's Euler characteristic, boundary loops,
// components and, with `keep_parts`, parts. Errors begin with `where`.
Status check_simplified(const Topology& now, const TopologyStats& initial, bool keep_parts,
                        const std::string& where);

class CollapseMesh {
 public:
  explicit CollapseMesh(const Topology& topology);

  uint32_t vertex_count() const { return static_cast<uint32_t>(list_start_.size()); }
  const Face& face(uint32_t f) const { return faces_[f]; }
  bool face_alive(uint32_t f) const { return faces_[f].v[0] != kNoVertex; }
  std::span<const uint32_t> faces_of(uint32_t v) const {
    return {islands_[island_of(v)].pool.data() + list_start_[v], list_size_[v]};
  }
  bool vertex_alive(uint32_t v) const { return list_size_[v] > 0; }
  uint32_t live_vertices() const;
  size_t live_faces() const;

  // Makes islands: vertex v goes to island island_of[v] (< count: unions of connected components,
  // or regions, regions.h), up to `threads` laid out at once. The lists keep their faces in their
  // order.
  void split_into_islands(std::vector<uint16_t> island_of, size_t count, unsigned threads);
  size_t island_count() const { return islands_.size(); }
  uint32_t island_of(uint32_t v) const { return island_of_.empty() ? 0 : island_of_[v]; }
  uint32_t island_live_vertices(size_t i) const { return islands_[i].live_vertices; }
  // visit(v) for each vertex of island i, ascending.
  template <class Visit>
  void for_each_island_vertex(size_t i, Visit&& visit) const {
    for (const auto& [begin, end] : islands_[i].runs)
      for (uint32_t v = begin; v < end; ++v) visit(v);
  }

  // Vertices joined to v by an edge, and vertices sharing a face with v (second-order
  // neighbours, paper §2); each once, v excluded. `out` is cleared first.
  void neighbours(uint32_t v, std::vector<uint32_t>& out) const;
  void second_order_neighbours(uint32_t v, std::vector<uint32_t>& out) const;

  // Performs the half-edge collapse v0 → v1 (legality checked by the caller) and fills the
  // record's wings and moved faces (moved_faces points into `moved`).
  void collapse(uint32_t v0, uint32_t v1, CollapseRecord& record, std::vector<uint32_t>& moved);

  // The live mesh as a Topology: faces in input order, vertices renumbered in input order;
  // original_vertex maps new → input vertex.
  Topology to_topology(const Topology& input, std::vector<uint32_t>& original_vertex) const {
    return live_topology(input, faces_, original_vertex);
  }

 private:
  struct Island {
    // Its vertices as runs [begin, end) of consecutive numbers (a mesh's parts are mostly
    // numbered in runs: a few bytes an island where a list took 4 B a vertex).
    std::vector<std::pair<uint32_t, uint32_t>> runs;
    std::vector<uint32_t> pool;  // the face lists of its vertices
    uint32_t live_vertices = 0;
    size_t live_faces = 0;  // faces whose first corner lies in it
  };
  void remove_face_from(uint32_t v, uint32_t f);
  void reserve_list(uint32_t v, uint32_t size);
  void compact_pool(Island& island, uint32_t extra);
  // Lays out the lists of `island`'s vertices in its pool, with room to grow.
  void lay_out(Island& island);
  template <class Visit>
  void for_each_member(const Island& island, Visit&& visit) const {
    for_each_island_vertex(static_cast<size_t>(&island - islands_.data()), visit);
  }

  std::vector<Face> faces_;
  std::vector<uint32_t> list_start_, list_size_, list_capacity_;  // list_start_: into its pool
  std::vector<Island> islands_;
  std::vector<uint16_t> island_of_;  // empty while there is one island
};

}  // namespace dynpm::simplification
