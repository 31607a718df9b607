// The collapse's legality rules, one fixture each, including the paper's Figures 4 and 5.
#include <gtest/gtest.h>

#include "fixtures.h"
#include "simplify/collapse_mesh.h"
#include "simplify/legality.h"

namespace dynpm {
namespace {

using simplification::CollapseMesh;
using simplification::VertexMarks;

std::vector<uint32_t> faces_of_edge(const CollapseMesh& mesh, uint32_t v0, uint32_t v1) {
  std::vector<uint32_t> out;
  for (uint32_t f : mesh.faces_of(v0))
    if (mesh.face(f).contains(v1)) out.push_back(f);
  return out;
}

bool p1_star(const CollapseMesh& mesh, uint32_t v0, uint32_t v1) {
  VertexMarks marks;
  return simplification::second_order_neighbours_ok(mesh, v0, v1, faces_of_edge(mesh, v0, v1),
                                                    marks);
}

// Figure 4, triangles: the inner vertex 2 has valence 3 (faces 0-1-2, 1-3-2, 3-0-2). Collapsing
// 0 → 1 would leave it with valence 2. Vertex 3 is joined to both 0 and 1 but shares no face
// with both: (P1) and (P1*) reject.
//          3
//        / | \     (3 joined to 0, 1 and 2)
//       0--2--1       plus triangle (1, 0, 4) below the edge
//        \   /
//          4
Topology figure_4() {
  Topology t = Topology::with_vertices(5);
  t.add_triangle(0, 1, 2);
  t.add_triangle(1, 3, 2);
  t.add_triangle(3, 0, 2);
  t.add_triangle(1, 0, 4);
  return t;
}

// Figure 5, quads: vertex 2 (inner, valence 3) lies in triangle (0, 1, 2) and in the quads
// (2, 1, 4, 3) and (2, 3, 5, 0). Collapsing 0 → 1 leaves 2 with valence 2. Vertex 3 is no
// edge-neighbour of 0 or 1 (it is across the quads' diagonals), so (P1) passes; but it shares a
// face with each, and none with both: (P1*) rejects.
//    5 ---- 3 ---- 4
//    |      |      |
//    |      2      |
//    |    /   \    |
//    0 ---------- 1
Topology figure_5() {
  Topology t = Topology::with_vertices(6);
  t.add_triangle(0, 1, 2);
  t.add_quad(2, 1, 4, 3);
  t.add_quad(2, 3, 5, 0);
  return t;
}

TEST(Legality, Figure4BothP1AndP1StarReject) {
  const Topology t = figure_4();
  ASSERT_TRUE(validate(t).ok());
  const CollapseMesh mesh(t);
  EXPECT_FALSE(simplification::first_order_neighbours_ok(mesh, 0, 1));
  EXPECT_FALSE(p1_star(mesh, 0, 1));
  // A legal collapse in the same mesh: 4 → 0 along the lower boundary passes both.
  EXPECT_TRUE(simplification::first_order_neighbours_ok(mesh, 4, 0));
  EXPECT_TRUE(p1_star(mesh, 4, 0));
}

TEST(Legality, Figure5P1PassesP1StarRejects) {
  const Topology t = figure_5();
  ASSERT_TRUE(validate(t).ok());
  const CollapseMesh mesh(t);
  EXPECT_TRUE(simplification::first_order_neighbours_ok(mesh, 0, 1));
  EXPECT_FALSE(p1_star(mesh, 0, 1));

  // What (P1*) prevents: doing the collapse anyway breaks (M2) at vertex 2.
  CollapseMesh forced(t);
  CollapseRecord record;
  std::vector<uint32_t> moved;
  forced.collapse(0, 1, record, moved);
  std::vector<uint32_t> original;
  const ValidationReport report = validate(forced.to_topology(t, original));
  EXPECT_EQ(report.count(ProblemKind::kInnerValence), 1u);
}

TEST(Legality, QuadEdgeCollapseNeedsNoMoreThanP2) {
  // Paper §2: collapsing an edge between quads only turns the quads into triangles.
  const auto grid = test::quad_grid(3, 3);
  const CollapseMesh mesh(grid.topology);
  EXPECT_TRUE(p1_star(mesh, 5, 6));  // an inner edge
  CollapseMesh after(grid.topology);
  CollapseRecord record;
  std::vector<uint32_t> moved;
  after.collapse(5, 6, record, moved);
  ASSERT_EQ(record.wing_count, 2);
  EXPECT_FALSE(record.wings[0].was_triangle());
  EXPECT_FALSE(record.wings[1].was_triangle());
  std::vector<uint32_t> original;
  const Topology t = after.to_topology(grid.topology, original);
  EXPECT_TRUE(validate(t).ok());
  EXPECT_EQ(t.faces.size(), 9u);  // no face vanished
  EXPECT_EQ(t.triangle_count(), 2u);
  EXPECT_EQ(t.quad_count(), 7u);
}

TEST(Legality, WingsNameVZeroOtherNeighbour) {
  // Triangle case: the wing vertex is the triangle's third corner; quad case: the corner next
  // to v0 away from v1.
  const auto strip = test::tri_quad_strip();
  CollapseMesh mesh(strip.topology);
  CollapseRecord record;
  std::vector<uint32_t> moved;
  mesh.collapse(7, 2, record, moved);  // edge 2-7 lies in triangle (2, 7, 6) only
  ASSERT_EQ(record.wing_count, 1);
  EXPECT_TRUE(record.wings[0].was_triangle());
  EXPECT_EQ(record.wings[0].vertex, 6u);

  CollapseMesh quads(strip.topology);
  quads.collapse(0, 1, record, moved);  // edge 0-1 lies in quad (0, 1, 4, 3)
  ASSERT_EQ(record.wing_count, 1);
  EXPECT_FALSE(record.wings[0].was_triangle());
  EXPECT_EQ(record.wings[0].vertex, 3u);
  EXPECT_TRUE(record.wings[0].v1_follows_v0());
}

}  // namespace
}  // namespace dynpm
