// The shell surface of solid elements, for readers of solver results (Exodus II, d3plot) whose
// models are made of bricks, tetrahedra and wedges rather than shells: the faces used by
// exactly one solid cell are the outer (boundary) surface, oriented outward.
//
// Corner order is the one Exodus II, VTK and LS-DYNA share for linear cells:
//   tet      0 1 2 base (counter-clockwise seen from corner 3), 3 apex
//   pyramid  0 1 2 3 base (counter-clockwise seen from the apex), 4 apex
//   wedge    0 1 2 bottom triangle, 3 4 5 the top one above it
//   hex      0 1 2 3 bottom quad, 4 5 6 7 the top one above it
// Repeated corners (LS-DYNA writes tetrahedra and wedges as degenerate hexes) shrink a face to a
// triangle or drop it, so a degenerate hex yields the faces of the cell it stands for.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "dynpm/core.h"

namespace dynpm::io {

enum class SolidKind { kTet, kPyramid, kWedge, kHex };

// Number of corners of a kind: 4, 5, 6, 8.
int corner_count(SolidKind kind);

class SolidSurface {
 public:
  // corners: corner_count(kind) vertex indices.
  void add_cell(SolidKind kind, std::span<const uint32_t> corners, int32_t part,
                int64_t element_id);
  size_t cell_count() const { return cell_part_.size(); }
  // Appends the faces used by exactly one cell to topology (with the cell's part and element
  // id) in the order the cells were added; returns how many were appended. cells, when given,
  // receives the cell (in add_cell order) of each appended face, for element results.
  size_t append_outer_faces(Topology& topology, std::vector<uint32_t>* cells = nullptr) const;

 private:
  struct CellFace {
    std::array<uint32_t, 4> key;  // sorted corners: equal for the two sides of an inner face
    Face face;
    uint32_t cell;
  };
  std::vector<CellFace> faces_;
  std::vector<int32_t> cell_part_;
  std::vector<int64_t> cell_element_;
};

// Keeps only the vertices some face uses, renumbered in their original order, and shrinks
// node_ids with them. Returns, per kept vertex, its index before; empty when every vertex was
// used (the numbering did not change).
std::vector<uint32_t> drop_unused_vertices(Topology& topology);

}  // namespace dynpm::io
