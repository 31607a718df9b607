// Property tests on seeded random mixed meshes (random_meshes.h), 1 of 3: each mesh goes through
// simplify() with random targets, key steps and options, validated after every collapse: the
// result is valid, keeps its shape counts, and stops where it says.
// A failure names its seed (SCOPED_TRACE) and the mesh it made (random_meshes.h).
#include <gtest/gtest.h>

#include <array>
#include <cfloat>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include "random_meshes.h"
#include "round_trip.h"

namespace dynpm {
namespace {

using namespace test;

// Twice the area of a face in the measure the simplifier keeps positive: a triangle's cross
// product, a quad's diagonals crossed.
double doubled_area(const Face& f, std::span<const float> xyz) {
  auto p = [&](int c) {
    const float* q = &xyz[size_t{f.v[c]} * 3];
    return std::array<double, 3>{q[0], q[1], q[2]};
  };
  auto sub = [](auto a, auto b) {
    return std::array<double, 3>{a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  };
  const auto u = f.is_triangle() ? sub(p(1), p(0)) : sub(p(2), p(0));
  const auto w = f.is_triangle() ? sub(p(2), p(0)) : sub(p(3), p(1));
  const double x = u[1] * w[2] - u[2] * w[1], y = u[2] * w[0] - u[0] * w[2],
               z = u[0] * w[1] - u[1] * w[0];
  return std::sqrt(x * x + y * y + z * z);
}

// ---------------------------------------------------------------------------------------------
// 1. simplify(): valid after every collapse, stops where it says

TEST(PropertySimplify, RandomMixedMeshesStayValidAfterEveryCollapse) {
  for (uint32_t seed : seeds(1000, 16)) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Rng rng(seed);
    const RandomCase c = random_case(rng, 1200);
    SCOPED_TRACE(c.description);
    const Animation& a = c.animation;
    const ValidationReport input_report = validate(a);
    ASSERT_TRUE(input_report.ok()) << input_report.problems.front().message;
    ASSERT_EQ(input_report.count(ProblemKind::kUnreferencedVertex), 0u);
    ASSERT_EQ(input_report.count(ProblemKind::kNonManifoldEdge) > 0, c.ribs > 0);
    const Shape input_shape = shape_of(a.topology);
    const uint32_t n = a.topology.vertex_count;

    for (int run = 0; run < 2; ++run) {
      SimplifyOptions o = random_options(rng, a);
      switch (pick(rng, 0, 3)) {
        case 0: o.target_ratio = chance(rng, 0.1) ? 1.0 : uniform(rng, 0.01, 1); break;
        case 1: o.target_vertices = pick(rng, 1, n + 5); break;
        case 2: o.target_faces = pick(rng, 1, uint32_t(a.topology.faces.size())); break;
        default: o.max_error = chance(rng, 0.2) ? 0.0 : uniform(rng, 0, 0.03); break;
      }
      o.check_every_collapse = true;
      SCOPED_TRACE(describe(o));
      auto r = simplify(a.topology, a.frames, o);
      ASSERT_TRUE(r.ok()) << r.message();
      const Topology& t = r->topology;
      expect_clean(t, "result");
      EXPECT_EQ(shape_of(t), input_shape);
      EXPECT_EQ(r->collapses, n - t.vertex_count);
      ASSERT_EQ(r->original_vertex.size(), t.vertex_count);
      ASSERT_TRUE(std::is_sorted(r->original_vertex.begin(), r->original_vertex.end()));

      // Where it stopped: at the target exactly, or where no legal collapse remains.
      uint32_t target = o.target_vertices.value_or(0);
      if (o.target_ratio) target = std::max(target, uint32_t(std::ceil(*o.target_ratio * n)));
      if (r->target_reached) {
        if (target) {
          EXPECT_EQ(t.vertex_count, std::min(target, n));
        }
        if (o.target_faces) {
          EXPECT_LE(t.faces.size(), *o.target_faces);
        }
        if (o.max_error) {
          EXPECT_LE(r->max_error, *o.max_error);
        }
      } else {
        EXPECT_NE(r->stop_reason.find("no legal collapse remains"), std::string::npos)
            << r->stop_reason;
        EXPECT_GT(t.vertex_count, target);
        if (o.target_faces) {
          EXPECT_GT(t.faces.size(), *o.target_faces);
        }
      }

      // Live faces keep the input's order, parts and element numbers.
      size_t next = 0;
      for (size_t f = 0; f < t.faces.size(); ++f) {
        while (next < a.topology.faces.size() && a.topology.element_ids[next] != t.element_ids[f])
          ++next;
        ASSERT_LT(next, a.topology.faces.size()) << "face " << f << " is out of the input's order";
        EXPECT_EQ(t.part_ids[f], a.topology.part_ids[next]);
        ++next;
      }
      // Locked vertices stay; a joint never vanishes (its ends are locked), nor a part whose
      // boundary is kept; no face is left without area in a key step.
      for (uint32_t v : o.locked_vertices)
        EXPECT_TRUE(std::binary_search(r->original_vertex.begin(), r->original_vertex.end(), v))
            << "locked vertex " << v;
      if (c.ribs > 0) {
        EXPECT_GT(topology_stats(t, Adjacency::build(t)).non_manifold_edges, 0u);
      }
      if (o.keep_part_boundaries) {
        EXPECT_EQ(t.parts(), a.topology.parts());
      }
      BoundingBox box;
      for (size_t k : r->key_steps) box.extend(a.frames.step(k));
      for (size_t k : r->key_steps) {
        std::vector<float> xyz;
        for (uint32_t v : r->original_vertex)
          xyz.insert(xyz.end(), &a.frames.step(k)[size_t{v} * 3],
                     &a.frames.step(k)[size_t{v} * 3] + 3);
        for (size_t f = 0; f < t.faces.size(); ++f)
          ASSERT_GT(doubled_area(t.faces[f], xyz), 1e-12 * box.diagonal() * box.diagonal())
              << "face " << f << " in key step " << k;
      }
    }
  }
}

}  // namespace
}  // namespace dynpm
