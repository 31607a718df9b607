// dynpm/split_record.h — the split record: what one half-edge collapse removes and the vertex
// split that undoes it puts back (paper §4: vsp(p0, vl, vr, tl, tr)). One definition, followed
// under the same names from the collapse (CollapseRecord, simplify.h) through the progressive
// mesh (ProgressiveMesh, progressive.h) and the file (docs/FORMAT.md) to the viewer's decoder
// (viewer/src, in camelCase: parent, error, wingStart, wingFace, wingVertex, wingFlags,
// movedStart, movedFaces, WING_WAS_TRIANGLE, WING_V1_FOLLOWS_V0, WING_SLOT_SHIFT).
//
// The half-edge collapse v0 → v1 (paper Fig. 2 and 3). Faces holding both vertices lose v0:
// a triangle vanishes, a quad becomes a triangle. Every other face of v0 takes v1. v1 keeps
// its position in every time step, so every level of detail uses original positions.
//
//   triangles (Fig. 2): fl, fr vanish          quads (Fig. 3): fl, fr become triangles
//
//     ---- wl ----            ---- wl ----       wl ----- x ---          wl ----- x ---
//     \   /  \   /            \     \    /       |   fl   |              |  \  fl |
//      \ / fl \ /              \     \  /        |        |              |    \   |
//     - v0 ---- v1 -   ==>    ------ v1 -        v0 ----- v1 ---   ==>   |      v1 ---
//      / \ fr / \              /     /  \        |   fr   |              |    /   |
//     /   \  /   \            /     /    \       |        |              |  /  fr |
//     ---- wr ----            ---- wr ----       wr ----- y ---          wr ----- y ---
//
// A split, read from right to left, re-inserts v0. Its fields:
//   parent       v1, the vertex the split starts from (it keeps its position)
//   new vertex   v0; not stored: split i creates vertex base_vertex_count + i
//   error        the simplification error of the mesh right after the split
//   wings        the faces of the edge (v0, v1) — fl and fr above: 1 at a boundary, 2 inside,
//                3 or 4 at a T-joint of shells — each a SplitWing
//   moved_faces  v0's other faces: the collapse gave them v1, the split gives them back to v0
//                (listed, since v1's own faces stay with it; docs/FORMAT.md)
//
// The wing vertex of a face of the edge is v0's other neighbour in that face: the third corner
// of a triangle, the corner next to v0 away from v1 in a quad (wl, wr above). The split
// re-creates a triangle wing (tl, tr of the paper say whether the face was a triangle) or
// turns a quad wing back from the triangle the collapse left.
#pragma once

#include <cstdint>

namespace dynpm {

// One wing of a split: a face of the edge (v0, v1) before the collapse. The .dpm file stores
// exactly these flags (docs/FORMAT.md).
struct SplitWing {
  uint32_t face = 0;    // a re-created triangle's face id, or the quad's face id
  uint32_t vertex = 0;  // w: v0's other neighbour in the face
  uint8_t flags = 0;    // kWasTriangle | kV1FollowsV0 | v0's corner slot << kSlotShift

  static constexpr uint8_t kWasTriangle = 1;  // the face vanished (else a quad lost v0)
  static constexpr uint8_t kV1FollowsV0 = 2;  // orientation: v1 comes right after v0 in it
  static constexpr int kSlotShift = 2;        // v0's corner slot (0-3) before the collapse
  bool was_triangle() const { return (flags & kWasTriangle) != 0; }
  bool v1_follows_v0() const { return (flags & kV1FollowsV0) != 0; }
  int v0_slot() const { return (flags >> kSlotShift) & 3; }
};

}  // namespace dynpm
