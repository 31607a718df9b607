// The simplifier on whole meshes: validity after every collapse, exact targets, features that
// only slide, T-joints that never open, and real CalculiX results.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "dynpm/io.h"
#include "dynpm/simplify.h"
#include "fixtures.h"

namespace dynpm {
namespace {

Result<SimplifyResult> simplify_checked(const test::Mesh& m, SimplifyOptions options) {
  options.check_every_collapse = true;
  const Animation a = m.animation();
  return simplify(a.topology, a.frames, options);
}

// A quad grid whose height varies, so collapses have different costs.
test::Mesh wavy_grid(uint32_t nx, uint32_t ny) {
  auto m = test::quad_grid(nx, ny);
  for (size_t v = 0; v < m.positions.size(); v += 3)
    m.positions[v + 2] =
        0.3f * std::sin(m.positions[v] * 0.9f) * std::cos(m.positions[v + 1] * 0.7f);
  return m;
}

// The grid with the quads of every third column split into two triangles: a mixed mesh.
test::Mesh mixed_grid(uint32_t nx, uint32_t ny) {
  auto m = wavy_grid(nx, ny);
  Topology t = Topology::with_vertices(m.topology.vertex_count);
  for (size_t f = 0; f < m.topology.faces.size(); ++f) {
    const Face& q = m.topology.faces[f];
    if (f % 3 == 0) {
      t.add_triangle(q.v[0], q.v[1], q.v[2]);
      t.add_triangle(q.v[0], q.v[2], q.v[3]);
    } else {
      t.add_face(q);
    }
  }
  m.topology = t;
  return m;
}

TEST(Simplify, QuadGridStaysValidAfterEveryCollapseAndLeavesTriangles) {
  const auto m = wavy_grid(8, 8);
  SimplifyOptions options;
  options.target_vertices = 20;
  auto r = simplify_checked(m, options);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->topology.vertex_count, 20u);
  EXPECT_TRUE(r->target_reached);
  EXPECT_GT(r->topology.triangle_count(), 0u);  // collapsed quads became triangles
  EXPECT_TRUE(validate(r->topology).ok());
}

TEST(Simplify, MixedMeshStaysValidAfterEveryCollapse) {
  const auto m = mixed_grid(9, 7);
  for (uint32_t target : {60u, 30u, 12u}) {
    SimplifyOptions options;
    options.target_vertices = target;
    auto r = simplify_checked(m, options);
    ASSERT_TRUE(r.ok()) << r.message();
    EXPECT_EQ(r->topology.vertex_count, target);
  }
}

TEST(Simplify, ExactVertexCountOrSaysWhyNot) {
  const auto m = wavy_grid(20, 20);
  for (uint32_t target : {400u, 123u, 50u, 9u}) {
    SimplifyOptions options;
    options.target_vertices = target;
    auto r = simplify(m.topology, m.animation().frames, options);
    ASSERT_TRUE(r.ok()) << r.message();
    EXPECT_EQ(r->topology.vertex_count, target);
  }
  // A single quad collapses into a triangle, which (P3) keeps: at a boundary a mesh keeps more
  // than 3 vertices before a collapse.
  const auto quad = test::quad_grid(1, 1);
  SimplifyOptions options;
  options.target_vertices = 1;
  auto r = simplify(quad.topology, quad.animation().frames, options);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->topology.vertex_count, 3u);
  EXPECT_EQ(r->topology.triangle_count(), 1u);
  EXPECT_FALSE(r->target_reached);
  EXPECT_NE(r->stop_reason.find("no legal collapse remains"), std::string::npos);
}

TEST(Simplify, TargetFacesAndRatio) {
  const auto m = wavy_grid(12, 12);
  SimplifyOptions by_faces;
  by_faces.target_faces = 40;
  auto r = simplify(m.topology, m.animation().frames, by_faces);
  ASSERT_TRUE(r.ok());
  EXPECT_LE(r->topology.faces.size(), 40u);
  EXPECT_GT(r->topology.faces.size(), 30u);
  SimplifyOptions by_ratio;
  by_ratio.target_ratio = 0.5;
  r = simplify(m.topology, m.animation().frames, by_ratio);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(r->topology.vertex_count, 85u);  // ceil(0.5 · 169)
}

TEST(Simplify, MaxErrorStopsBeforeTheLimit) {
  auto m = wavy_grid(12, 12);
  SimplifyOptions options;
  options.max_error = 0.002;
  auto r = simplify(m.topology, m.animation().frames, options);
  ASSERT_TRUE(r.ok());
  EXPECT_LE(r->max_error, 0.002);
  EXPECT_LT(r->topology.vertex_count, 169u);
  EXPECT_TRUE(r->target_reached);
}

TEST(Simplify, FlatRegionsGoFirstAndBoundaryStaysOnItsLines) {
  // A flat grid: every collapse costs nothing, and the boundary only slides along the square's
  // sides, so every boundary vertex of the result lies on one of them and the corners stay.
  const auto m = test::quad_grid(10, 10);
  SimplifyOptions options;
  options.target_vertices = 8;
  auto r = simplify_checked(m, options);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->max_error, 0.0);
  const Adjacency adjacency = Adjacency::build(r->topology);
  for (uint32_t v = 0; v < r->topology.vertex_count; ++v) {
    if (!(adjacency.vertex_kind(v) & kBoundaryVertex)) continue;
    const uint32_t original = r->original_vertex[v];
    const float x = m.positions[original * 3], y = m.positions[original * 3 + 1];
    EXPECT_TRUE(x == 0 || x == 10 || y == 0 || y == 10) << "vertex " << original;
  }
  std::set<uint32_t> kept(r->original_vertex.begin(), r->original_vertex.end());
  for (uint32_t corner : {0u, 10u, 110u, 120u}) EXPECT_TRUE(kept.count(corner)) << corner;
}

TEST(Simplify, LockedVerticesStay) {
  const auto m = wavy_grid(10, 10);
  SimplifyOptions options;
  options.target_vertices = 15;
  options.locked_vertices = {12, 48, 60, 73};
  auto r = simplify_checked(m, options);
  ASSERT_TRUE(r.ok()) << r.message();
  std::set<uint32_t> kept(r->original_vertex.begin(), r->original_vertex.end());
  for (uint32_t v : options.locked_vertices) EXPECT_TRUE(kept.count(v)) << v;
}

// A panel (part 1, z = 0, 8 × 4 quads) with a rib (part 2, 8 × 3 quads in the plane y = 2)
// welded along its middle line: the edges of the line y = 2 have three faces.
test::Mesh panel_with_rib() {
  test::Mesh m = test::quad_grid(8, 4, 1);
  const uint32_t panel_vertices = m.topology.vertex_count;
  auto line = [](uint32_t i) { return 2 * 9 + i; };  // panel vertex (i, 2)
  auto rib = [&](uint32_t i, uint32_t k) {
    return k == 0 ? line(i) : panel_vertices + (k - 1) * 9 + i;
  };
  m.topology.vertex_count += 3 * 9;
  for (uint32_t k = 1; k <= 3; ++k)
    for (uint32_t i = 0; i <= 8; ++i) {
      m.positions.insert(m.positions.end(), {float(i), 2.f, float(k) * 0.8f});
      m.topology.node_ids.push_back(int64_t(m.topology.node_ids.size()) + 1);
    }
  for (uint32_t k = 0; k < 3; ++k)
    for (uint32_t i = 0; i < 8; ++i)
      m.topology.add_quad(rib(i, k), rib(i + 1, k), rib(i + 1, k + 1), rib(i, k + 1), 2);
  return m;
}

TEST(Simplify, TJointNeverOpens) {
  const auto m = panel_with_rib();
  const ValidationReport input = validate(m.animation());
  ASSERT_TRUE(input.ok());
  ASSERT_EQ(input.count(ProblemKind::kNonManifoldEdge), 8u);
  for (uint32_t target : {40u, 25u, 14u}) {
    SimplifyOptions options;
    options.target_vertices = target;
    auto r = simplify_checked(m, options);  // checks boundary loops and components every step
    ASSERT_TRUE(r.ok()) << r.message();
    // The joint is still there, and every vertex on it is shared by panel and rib faces.
    const TopologyStats stats = topology_stats(r->topology, Adjacency::build(r->topology));
    EXPECT_GE(stats.non_manifold_edges, 1u);
    std::map<uint32_t, std::set<int32_t>> parts_at;
    for (size_t f = 0; f < r->topology.faces.size(); ++f)
      for (uint32_t c : r->topology.faces[f].v)
        if (c != kNoVertex) parts_at[c].insert(r->topology.part_ids[f]);
    for (uint32_t v = 0; v < r->topology.vertex_count; ++v) {
      const uint32_t original = r->original_vertex[v];
      const bool on_line = original < 45 && original / 9 == 2;
      if (on_line) {
        EXPECT_EQ(parts_at[v].size(), 2u) << "joint vertex " << original << " lost a shell";
      }
      // Vertices of the joint only slid along it: nothing off the line carries both parts.
      if (parts_at[v].size() == 2) {
        EXPECT_TRUE(on_line) << "vertex " << original;
      }
    }
  }
}

TEST(Simplify, RibsKeepAFaceOnTheirJointToTheEnd) {
  // Simplified until no legal collapse remains, a rib shrinks to one triangle on its joint; the
  // collapse that would delete that triangle (the joint would drop to two faces, the rib would
  // be gone) is not legal. Found by tests/property_test.cpp.
  for (bool triangles : {false, true}) {
    auto m = panel_with_rib();
    if (triangles) {  // the rib's quads split into triangles
      Topology t = Topology::with_vertices(m.topology.vertex_count);
      for (size_t f = 0; f < m.topology.faces.size(); ++f) {
        const Face& q = m.topology.faces[f];
        if (m.topology.part_ids[f] == 2) {
          t.add_triangle(q.v[0], q.v[1], q.v[2], 2);
          t.add_triangle(q.v[0], q.v[2], q.v[3], 2);
        } else {
          t.add_face(q, m.topology.part_ids[f]);
        }
      }
      m.topology = t;
    }
    for (bool parts : {true, false}) {
      SimplifyOptions options;
      options.keep_part_boundaries = parts;
      auto r = simplify_checked(m, options);
      ASSERT_TRUE(r.ok()) << r.message();
      EXPECT_GE(topology_stats(r->topology, Adjacency::build(r->topology)).non_manifold_edges, 1u);
    }
  }
}

TEST(Simplify, PartEnclosedByAnotherKeepsAFace) {
  // A square of part 2 (1 × 1 to 3 × 3 cells, quads or split) inside part 1: its boundary only
  // slides, so even simplified to the end the part keeps a face.
  for (bool triangles : {false, true}) {
    for (uint32_t size : {1u, 2u, 3u}) {
      auto m = wavy_grid(7, 7);
      Topology t = Topology::with_vertices(m.topology.vertex_count);
      for (size_t f = 0; f < m.topology.faces.size(); ++f) {
        const uint32_t i = f % 7, j = f / 7;
        const int32_t part = i >= 3 && i < 3 + size && j >= 3 && j < 3 + size ? 2 : 1;
        const Face& q = m.topology.faces[f];
        if (triangles) {
          t.add_triangle(q.v[0], q.v[1], q.v[2], part);
          t.add_triangle(q.v[0], q.v[2], q.v[3], part);
        } else {
          t.add_face(q, part);
        }
      }
      m.topology = t;
      auto r = simplify_checked(m, SimplifyOptions{});
      ASSERT_TRUE(r.ok()) << r.message();
      EXPECT_EQ(r->topology.parts(), (std::vector<int32_t>{1, 2})) << size << " × " << size;
    }
  }
}

TEST(Simplify, PartBoundariesOnlySlideAlongThemselves) {
  // Two parts side by side in one plane, joined along x = 5.
  auto m = wavy_grid(10, 6);
  for (size_t f = 0; f < m.topology.faces.size(); ++f)
    m.topology.part_ids[f] = (f % 10) < 5 ? 1 : 2;
  SimplifyOptions options;
  options.target_vertices = 20;
  auto r = simplify_checked(m, options);
  ASSERT_TRUE(r.ok()) << r.message();
  for (size_t f = 0; f < r->topology.faces.size(); ++f) {
    for (uint32_t c : r->topology.faces[f].v) {
      if (c == kNoVertex) continue;
      const float x = m.positions[r->original_vertex[c] * 3];
      // Faces of part 1 stay left of the joint, part 2 right of it.
      if (r->topology.part_ids[f] == 1)
        EXPECT_LE(x, 5.f);
      else
        EXPECT_GE(x, 5.f);
    }
  }
}

TEST(Simplify, ListenerSeesEveryCollapse) {
  struct Counter : CollapseListener {
    size_t collapses = 0, wings = 0;
    void on_collapse(const CollapseRecord& r) override {
      ++collapses;
      wings += r.wing_count;
      EXPECT_NE(r.v0, r.v1);
      EXPECT_GE(r.wing_count, 1);
    }
  } counter;
  const auto m = mixed_grid(6, 6);
  SimplifyOptions options;
  options.target_vertices = 10;
  auto r = simplify(m.topology, m.animation().frames, options, &counter);
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(counter.collapses, r->collapses);
  EXPECT_EQ(r->collapses, 49u - 10u);
}

// Independent rounds: within a round no collapse removes or keeps a vertex that an earlier
// collapse of the round kept or left on its wings; the rounds follow one another, each at
// most its fraction of the vertices; the mesh stays valid and the target is reached exactly.
TEST(Simplify, IndependentRoundsKeepOffWhatTheirRoundChanged) {
  struct Rounds : CollapseListener {
    uint32_t round = 0;
    size_t in_round = 0, rounds = 0, largest = 0;
    std::set<uint32_t> touched;
    void on_collapse(const CollapseRecord& r) override {
      ASSERT_GE(r.round, round);
      if (r.round == 0) return;  // no rounds
      if (r.round != round) round = r.round, touched.clear(), in_round = 0, ++rounds;
      EXPECT_FALSE(touched.count(r.v0)) << "round " << r.round;
      EXPECT_FALSE(touched.count(r.v1)) << "round " << r.round;
      touched.insert(r.v1);
      for (int k = 0; k < r.wing_count; ++k) touched.insert(r.wings[k].vertex);
      largest = std::max(largest, ++in_round);
    }
  } seen;
  const auto m = mixed_grid(14, 12);
  const Animation a = m.animation();
  SimplifyOptions options;
  options.target_vertices = 12;
  options.independent_rounds = 0.1;
  options.check_every_collapse = true;
  auto r = simplify(a.topology, a.frames, options, &seen);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->topology.vertex_count, 12u);
  EXPECT_LE(seen.largest, size_t{15 * 13 / 10});  // a tenth of the 195 vertices
  EXPECT_GE(seen.rounds, 26u);  // 195 → 12 vertices, at most a tenth a round: ≥ 26 rounds
  // Without rounds the same collapses come in one sequence, every record's round 0.
  options.independent_rounds = 0;
  Rounds none;
  ASSERT_TRUE(simplify(a.topology, a.frames, options, &none).ok());
  EXPECT_EQ(none.rounds, 0u);
}

TEST(Simplify, OptimalPlacementNeedsEveryStepAsKeyStep) {
  auto a = wavy_grid(6, 6).animation();
  a.frames.add_step(std::vector<float>(a.frames.step(0).begin(), a.frames.step(0).end()), 1.0);
  SimplifyOptions options;
  options.target_vertices = 10;
  options.placement = Placement::kOptimal;
  options.key_steps = {0};
  EXPECT_FALSE(simplify(a.topology, a.frames, options).ok());
  options.key_steps = {};
  options.check_every_collapse = true;
  auto r = simplify(a.topology, a.frames, options);
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_EQ(r->key_step_positions.size(), 2u);
  EXPECT_EQ(r->key_step_positions[0].size(), 10u * 3);
}

TEST(Simplify, InvalidInputIsRefused) {
  auto m = test::valence_two_quads();
  SimplifyOptions options;
  options.target_vertices = 3;
  auto r = simplify(m.topology, m.animation().frames, options);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("(M2)"), std::string::npos) << r.message();
}

TEST(Simplify, CalculixCrashBoxStaysValidAfterEveryCollapse) {
  // The crushed tube (last step, folds everywhere at the top), validated after every collapse.
  const std::string path = test::shared_data() + "/crashbox-s/obj/frame_025.obj";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "../shared/data is not beside the project";
  auto mesh = read_mesh(path);
  ASSERT_TRUE(mesh.ok());
  SimplifyOptions options;
  options.target_ratio = 0.6;
  options.check_every_collapse = true;
  auto r = simplify(mesh->topology, mesh->frames, options);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_TRUE(r->target_reached);
}

TEST(Simplify, ShippedSampleKeepsQuadsAtHalfTheVertices) {
  // data/hat-rail, every step rating the collapses.
  auto paths = expand_inputs(std::vector<std::string>{test::sample_dir() + "/frame_*.obj"});
  ASSERT_TRUE(paths.ok());
  auto a = read_animation(*paths);
  ASSERT_TRUE(a.ok()) << a.message();
  SimplifyOptions options;
  options.target_ratio = 0.5;
  auto r = simplify(a->topology, a->frames, options);
  ASSERT_TRUE(r.ok()) << r.message();
  const double quad_share = double(r->topology.quad_count()) / double(r->topology.faces.size());
  std::printf("hat rail at 50%% of vertices: %zu quads, %zu triangles (quads %.0f%% of faces)\n",
              r->topology.quad_count(), r->topology.triangle_count(), 100 * quad_share);
  EXPECT_GT(quad_share, 0.5);  // 62 % when written
  EXPECT_TRUE(validate(r->topology).ok());
}

TEST(Simplify, CalculixMixedCrashBoxKeepsQuadsAtHalfTheVertices) {
  const std::string folder = test::shared_data() + "/crashbox-mixed-5k/obj";
  if (!std::filesystem::exists(folder)) GTEST_SKIP() << "../shared/data is not beside the project";
  for (const char* frame : {"frame_000.obj", "frame_040.obj"}) {
    auto mesh = read_mesh(folder + "/" + frame);
    ASSERT_TRUE(mesh.ok());
    SimplifyOptions options;
    options.target_ratio = 0.5;
    auto r = simplify(mesh->topology, mesh->frames, options);
    ASSERT_TRUE(r.ok()) << frame << ": " << r.message();
    const double quad_share = double(r->topology.quad_count()) / double(r->topology.faces.size());
    RecordProperty(std::string("quad_share_50pct_") + frame, std::to_string(quad_share));
    std::printf("%s at 50%% of vertices: %zu quads, %zu triangles (quads %.0f%% of faces)\n", frame,
                r->topology.quad_count(), r->topology.triangle_count(), 100 * quad_share);
    EXPECT_GT(quad_share, 0.6) << frame;
    EXPECT_TRUE(validate(r->topology).ok());
  }
}

}  // namespace
}  // namespace dynpm
