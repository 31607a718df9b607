// The field error (dynpm/eval.h: FieldPair) and evaluate_levels()'s field columns: checked
// against a brute-force closest point, on fields whose error is known (a linear field on a
// plane is kept by any triangulation of the plane, a quadratic one is not), for symmetry and
// thread-count independence, and on a built model whose one hot vertex must stay the peak.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

#include "dynpm/lod.h"
#include "dynpm/pipeline.h"
#include "fixtures.h"

namespace dynpm {
namespace {

struct Prepared {
  SurfaceTopology topology;
  Surface surface;
};

// On the heap: the surface points to its topology.
std::unique_ptr<Prepared> prepare(const test::Mesh& m, unsigned threads = 1) {
  auto p = std::make_unique<Prepared>();
  auto t = prepare_topology("mesh", m.topology);
  EXPECT_TRUE(t.ok()) << t.message();
  p->topology = std::move(t).value();
  auto s = prepare_surface("mesh", p->topology, m.positions, threads);
  EXPECT_TRUE(s.ok()) << s.message();
  p->surface = std::move(s).value();
  return p;
}

// A grid over [0, nx] × [0, ny] scaled to [0, 6]², bent by `bend` · sin(x) in z.
test::Mesh grid(uint32_t n, double bend) {
  test::Mesh m = test::quad_grid(n, n);
  for (size_t v = 0; v < m.positions.size(); v += 3) {
    m.positions[v] *= float(6.0 / n), m.positions[v + 1] *= float(6.0 / n);
    m.positions[v + 2] = float(bend * std::sin(m.positions[v]));
  }
  return m;
}

std::vector<float> node_field(const test::Mesh& m, double (*f)(double, double)) {
  std::vector<float> values;
  for (size_t v = 0; v < m.positions.size(); v += 3)
    values.push_back(float(f(m.positions[v], m.positions[v + 1])));
  return values;
}

// The field at the closest point of `to` to p, by trying every triangle.
double brute_force_value(const Point3& p, const test::Mesh& to, std::span<const float> values) {
  const auto triangles = surface_triangles(to.topology, to.positions);
  std::vector<float> corners;  // the field at each triangle's corners, as the BVH splits quads
  double best = INFINITY, value = 0;
  for (const SurfaceTriangle& t : triangles) {
    const Point3 a{t.a[0], t.a[1], t.a[2]}, b{t.b[0], t.b[1], t.b[2]}, c{t.c[0], t.c[1], t.c[2]};
    const Point3 q = closest_point_on_triangle(p, a, b, c);
    const double d2 = (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                      (q[2] - p[2]) * (q[2] - p[2]);
    if (d2 >= best) continue;
    best = d2;
    // Barycentric weights of q by areas (the triangles here are not degenerate).
    auto cross_length = [](const Point3& u, const Point3& v, const Point3& w) {
      const Point3 e{v[0] - u[0], v[1] - u[1], v[2] - u[2]},
          f{w[0] - u[0], w[1] - u[1], w[2] - u[2]};
      const double x = e[1] * f[2] - e[2] * f[1], y = e[2] * f[0] - e[0] * f[2],
                   z = e[0] * f[1] - e[1] * f[0];
      return std::sqrt(x * x + y * y + z * z);
    };
    const double whole = cross_length(a, b, c);
    const double wa = cross_length(q, b, c) / whole, wb = cross_length(a, q, c) / whole;
    const Face& face = to.topology.faces[t.face];
    auto at =
        [&](const std::array<float, 3>& corner) {  // a corner's value: a vertex or the centroid
          double sum = 0;
          for (int i = 0; i < face.degree(); ++i) {
            const float* x = &to.positions[3 * size_t{face.v[i]}];
            if (x[0] == corner[0] && x[1] == corner[1] && x[2] == corner[2])
              return double(values[face.v[i]]);
            sum += values[face.v[i]];
          }
          return sum / face.degree();
        };
    value = wa * at(t.a) + wb * at(t.b) + (1 - wa - wb) * at(t.c);
  }
  return value;
}

HausdorffOptions vertices_only() {
  HausdorffOptions o;
  o.sample_edges = false;
  o.samples_per_face = 0;
  o.threads = 1;
  return o;
}

TEST(FieldError, AtTheVerticesItIsTheDifferenceAtTheBruteForceClosestPoint) {
  const test::Mesh fine = grid(9, 0.5), coarse = grid(4, 0.8);
  auto f = [](double x, double y) { return x * x - 2 * y + std::sin(3 * x * y); };
  const std::vector<float> fine_values = node_field(fine, f), coarse_values = node_field(coarse, f);
  const auto a = prepare(fine), b = prepare(coarse);
  const FieldPair pair{{FieldLocation::kNode, fine_values}, {FieldLocation::kNode, coarse_values}};
  auto r = hausdorff(a->surface, b->surface, vertices_only(), {&pair, 1});
  ASSERT_TRUE(r.ok()) << r.message();
  double a_to_b = 0, b_to_a = 0;
  for (uint32_t v = 0; v < fine.topology.vertex_count; ++v) {
    const Point3 p{fine.positions[3 * v], fine.positions[3 * v + 1], fine.positions[3 * v + 2]};
    a_to_b =
        std::max(a_to_b, std::abs(fine_values[v] - brute_force_value(p, coarse, coarse_values)));
  }
  for (uint32_t v = 0; v < coarse.topology.vertex_count; ++v) {
    const Point3 p{coarse.positions[3 * v], coarse.positions[3 * v + 1],
                   coarse.positions[3 * v + 2]};
    b_to_a = std::max(b_to_a, std::abs(coarse_values[v] - brute_force_value(p, fine, fine_values)));
  }
  ASSERT_EQ(r->fields.size(), 1u);
  EXPECT_GT(a_to_b, 0.1);
  EXPECT_NEAR(r->fields[0].a_to_b, a_to_b, 1e-4);
  EXPECT_NEAR(r->fields[0].b_to_a, b_to_a, 1e-4);
  EXPECT_EQ(r->fields[0].max, std::max(r->fields[0].a_to_b, r->fields[0].b_to_a));

  // Two-sided: swapping the surfaces swaps the directions.
  const FieldPair swapped{pair.b, pair.a};
  auto s = hausdorff(b->surface, a->surface, vertices_only(), {&swapped, 1});
  ASSERT_TRUE(s.ok()) << s.message();
  EXPECT_EQ(s->fields[0].a_to_b, r->fields[0].b_to_a);
  EXPECT_EQ(s->fields[0].b_to_a, r->fields[0].a_to_b);
}

TEST(FieldError, ALinearFieldOnAPlaneIsKeptByACoarseGridAndAQuadraticOneIsNot) {
  const test::Mesh fine = grid(12, 0), coarse = grid(3, 0);
  const auto a = prepare(fine), b = prepare(coarse);
  HausdorffOptions options;
  options.threads = 1;
  auto error_of = [&](double (*f)(double, double)) {
    const std::vector<float> fa = node_field(fine, f), fb = node_field(coarse, f);
    const FieldPair pair{{FieldLocation::kNode, fa}, {FieldLocation::kNode, fb}};
    auto r = hausdorff(a->surface, b->surface, options, {&pair, 1});
    EXPECT_TRUE(r.ok()) << r.message();
    return r->fields[0].max;
  };
  EXPECT_LT(error_of([](double x, double y) { return 3 * x - y + 2; }), 1e-5);
  EXPECT_GT(error_of([](double x, double y) { return x * x + y; }), 0.1);
}

TEST(FieldError, AnElementFieldIsComparedFaceByFaceAndTheSameOnAnyThreadCount) {
  const test::Mesh fine = grid(8, 0), coarse = grid(4, 0);
  std::vector<float> fa, fb;  // each face's value: 1 on the left half, 0 on the right
  for (size_t f = 0; f < fine.topology.faces.size(); ++f) fa.push_back(f % 8 < 4 ? 1.f : 0.f);
  for (size_t f = 0; f < coarse.topology.faces.size(); ++f) fb.push_back(f % 4 < 2 ? 1.f : 0.f);
  std::vector<double> errors;
  for (unsigned threads : {1u, 2u, 3u}) {
    const auto a = prepare(fine, threads), b = prepare(coarse, threads);
    HausdorffOptions options;
    options.threads = threads;
    const FieldPair same{{FieldLocation::kElement, fa}, {FieldLocation::kElement, fb}};
    std::vector<float> flipped(fb.rbegin(), fb.rend());
    const FieldPair pairs[2] = {
        same, {{FieldLocation::kElement, fa}, {FieldLocation::kElement, flipped}}};
    auto r = hausdorff(a->surface, b->surface, options, pairs);
    ASSERT_TRUE(r.ok()) << r.message();
    // The halves meet on the same line in both grids: only samples within rounding of it can
    // land on the other side.
    EXPECT_NEAR(r->fields[0].max, 0, 1e-12) << threads;  // the weights sum to 1 ± rounding
    EXPECT_NEAR(r->fields[1].max, 1, 1e-12) << threads;
    for (const FieldDistance& d : r->fields) errors.insert(errors.end(), {d.a_to_b, d.b_to_a});
  }
  for (size_t i = 4; i < errors.size(); ++i) EXPECT_EQ(errors[i], errors[i % 4]);
}

// Two sheets 0.01 apart, stacked the same way up (test::two_sheets).
test::Mesh touching_sheets(float shift, std::vector<float>& values) {
  return test::two_sheets(grid(4, 0), shift, false, values);
}

// Shifted by 0.006, each sheet of B is nearer the other sheet of A (0.004) than its own: the
// closest point alone reads the wrong sheet's value. Within a tolerance of the shift the own
// sheet is a match too, and the error is the true one, not hidden when the values differ.
TEST(FieldError, WhereSheetsTouchTheToleranceFindsTheOwnSheet) {
  std::vector<float> fa, fb;
  const test::Mesh a_mesh = touching_sheets(0, fa), b_mesh = touching_sheets(0.006f, fb);
  const auto a = prepare(a_mesh), b = prepare(b_mesh);
  HausdorffOptions options;
  options.threads = 1;
  auto error_of = [&](double tolerance, const std::vector<float>& b_values) {
    options.field_tolerance = tolerance;
    const FieldPair pair{{FieldLocation::kNode, fa}, {FieldLocation::kNode, b_values}};
    auto r = hausdorff(a->surface, b->surface, options, {&pair, 1});
    EXPECT_TRUE(r.ok()) << r.message();
    return r->fields[0].max;
  };
  EXPECT_NEAR(error_of(0, fb), 1, 1e-6);
  EXPECT_NEAR(error_of(0.0061, fb), 0, 1e-6);
  std::vector<float> lower_half = fb;  // B's lower sheet reads 0.5: a real error of 0.5
  std::fill(lower_half.begin(), lower_half.begin() + lower_half.size() / 2, 0.5f);
  EXPECT_NEAR(error_of(0.0061, lower_half), 0.5, 1e-6);
}

// within() finds exactly the triangles a brute-force pass finds closer than the radius.
TEST(TriangleBvh, WithinIsEveryTriangleCloserThanTheRadius) {
  const test::Mesh m = grid(9, 0.7);
  const auto triangles = surface_triangles(m.topology, m.positions);
  const TriangleBvh bvh(triangles, 1);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> uniform(0, 1);
  for (int i = 0; i < 200; ++i) {
    const Point3 p{7 * uniform(random) - 0.5, 7 * uniform(random) - 0.5, 2 * uniform(random) - 1};
    const double radius = 1.5 * uniform(random);
    std::vector<TriangleBvh::Hit> hits;
    bvh.within(p, radius * radius, hits);
    std::vector<uint32_t> found, expected;
    for (const auto& h : hits) found.push_back(h.triangle);
    for (uint32_t t = 0; t < triangles.size(); ++t) {
      const SurfaceTriangle& s = triangles[t];
      const Point3 q = closest_point_on_triangle(
          p, {s.a[0], s.a[1], s.a[2]}, {s.b[0], s.b[1], s.b[2]}, {s.c[0], s.c[1], s.c[2]});
      const double d2 = (q[0] - p[0]) * (q[0] - p[0]) + (q[1] - p[1]) * (q[1] - p[1]) +
                        (q[2] - p[2]) * (q[2] - p[2]);
      if (d2 < radius * radius) expected.push_back(t);
    }
    std::sort(found.begin(), found.end());
    EXPECT_EQ(found, expected) << "query " << i;
  }
}

TEST(FieldError, AFieldOfTheWrongSizeIsAnError) {
  const test::Mesh m = grid(3, 0);
  const auto a = prepare(m);
  std::vector<float> short_field(5, 0.f), full(m.topology.vertex_count, 0.f);
  const FieldPair pair{{FieldLocation::kNode, full}, {FieldLocation::kNode, short_field}};
  auto r = hausdorff(a->surface, a->surface, vertices_only(), {&pair, 1});
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("5 field values for 16 vertices"), std::string::npos) << r.message();
}

}  // namespace
}  // namespace dynpm
