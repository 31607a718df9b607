#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "fixtures.h"

namespace dynpm {
namespace {

using test::quad_grid;

TEST(Adjacency, QuadGridCountsAndEuler) {
  const auto m = quad_grid(4, 3);
  const Adjacency adj = Adjacency::build(m.topology);
  const TopologyStats s = topology_stats(m.topology, adj);
  EXPECT_EQ(s.edges, 4u * 4 + 3u * 5);  // horizontal + vertical edges
  EXPECT_EQ(s.boundary_edges, 2u * (4 + 3));
  EXPECT_EQ(s.boundary_loops, 1u);
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.euler_characteristic, 1);  // a disc
  EXPECT_EQ(s.quads, 12u);
  EXPECT_EQ(s.triangles, 0u);
}

// Topology::parts(): the distinct part ids in ascending order, however the faces interleave them
// (runs, alternation, negative ids) and past the thousand parts where it sorts a copy instead.
TEST(Topology, PartsAreTheDistinctIdsInOrder) {
  const auto sorted_distinct = [](std::vector<int32_t> ids) {
    std::sort(ids.begin(), ids.end());
    ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
    return ids;
  };
  for (const size_t distinct : {size_t{1}, size_t{7}, size_t{1024}, size_t{1025}, size_t{5000}}) {
    Topology t;
    t.vertex_count = 3;
    uint32_t state = 12345;
    for (size_t f = 0; f < 20000; ++f) {
      state = state * 1103515245u + 12345u;
      const auto id = static_cast<int32_t>((state >> 8) % distinct) - 3;
      for (int run = 0; run < 1 + static_cast<int>(state % 3); ++run) t.add_triangle(0, 1, 2, id);
    }
    EXPECT_EQ(t.parts(), sorted_distinct(t.part_ids)) << distinct << " parts";
  }
  EXPECT_TRUE(Topology{}.parts().empty());
}

TEST(Adjacency, QuadDiagonalsAreNotEdges) {
  const auto m = quad_grid(1, 1);  // 0 1 / 2 3, quad (0, 1, 3, 2)
  const Adjacency adj = Adjacency::build(m.topology);
  EXPECT_TRUE(adj.find_edge(0, 1));
  EXPECT_TRUE(adj.find_edge(2, 0));
  EXPECT_FALSE(adj.find_edge(0, 3));
  EXPECT_FALSE(adj.find_edge(1, 2));
  EXPECT_EQ(adj.edge_count(), 4u);
}

TEST(Adjacency, VertexFacesAndEdgeFaces) {
  const auto m = quad_grid(2, 2);
  const Adjacency adj = Adjacency::build(m.topology);
  EXPECT_EQ(adj.faces_of_vertex(4).size(), 4u);  // the centre
  EXPECT_EQ(adj.faces_of_vertex(0).size(), 1u);  // a corner
  auto centre_edge = adj.find_edge(1, 4);
  ASSERT_TRUE(centre_edge);
  EXPECT_EQ(adj.faces_of_edge(*centre_edge).size(), 2u);
  EXPECT_EQ(adj.vertex_kind(4), kInteriorVertex);
  EXPECT_EQ(adj.vertex_kind(1), kBoundaryVertex);
}

TEST(Adjacency, TJointEdgeHasThreeFacesAndItsVerticesAreFeatures) {
  const auto m = test::t_joint();
  const Adjacency adj = Adjacency::build(m.topology);
  auto e = adj.find_edge(4, 1);
  ASSERT_TRUE(e);
  EXPECT_EQ(adj.faces_of_edge(*e).size(), 3u);
  EXPECT_TRUE(adj.is_feature_vertex(1));
  EXPECT_TRUE(adj.is_feature_vertex(4));
  EXPECT_FALSE(adj.is_feature_vertex(0));
  const TopologyStats s = topology_stats(m.topology, adj);
  EXPECT_EQ(s.non_manifold_edges, 1u);
  EXPECT_EQ(s.non_manifold_vertices, 2u);
  EXPECT_EQ(s.parts, 2u);
}

TEST(Adjacency, BowTieVertexHasTwoFans) {
  const auto m = test::bow_tie();
  const Adjacency adj = Adjacency::build(m.topology);
  EXPECT_TRUE(adj.vertex_kind(2) & kNonManifoldFan);
  EXPECT_FALSE(adj.vertex_kind(0) & kNonManifoldFan);
  EXPECT_EQ(topology_stats(m.topology, adj).non_manifold_vertices, 1u);
}

TEST(Adjacency, DisconnectedPartsAreComponents) {
  auto m = quad_grid(2, 1);
  // A second grid of 2 × 1 quads, numbered after the first.
  const auto other = quad_grid(2, 1);
  const uint32_t offset = m.topology.vertex_count;
  m.topology.vertex_count += other.topology.vertex_count;
  for (const Face& f : other.topology.faces)
    m.topology.add_quad(f.v[0] + offset, f.v[1] + offset, f.v[2] + offset, f.v[3] + offset, 7);
  const TopologyStats s = topology_stats(m.topology, Adjacency::build(m.topology));
  EXPECT_EQ(s.components, 2u);
  EXPECT_EQ(s.boundary_loops, 2u);
  EXPECT_EQ(s.parts, 2u);
}

TEST(Adjacency, UnreferencedVertexIsMarked) {
  auto m = quad_grid(1, 1);
  m.topology.vertex_count += 1;
  const Adjacency adj = Adjacency::build(m.topology);
  EXPECT_TRUE(adj.vertex_kind(4) & kUnreferencedVertex);
  const TopologyStats s = topology_stats(m.topology, adj);
  EXPECT_EQ(s.vertices, 5u);
  EXPECT_EQ(s.referenced_vertices, 4u);
}

}  // namespace
}  // namespace dynpm
