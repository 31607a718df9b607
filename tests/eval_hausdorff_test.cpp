// The Metro-style Hausdorff distance (src/eval): exact closest points, a BVH that answers like
// brute force, analytic distances, star-triangulated quads, determinism, and the CLI verb.
// The cross-check against CGAL is a separate program (cgal_hausdorff_check.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>

#include "dynpm/eval.h"
#include "dynpm/io.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

// Random numbers from std::mt19937's raw output, which the standard fixes everywhere.
class TestRandom {
 public:
  explicit TestRandom(uint32_t seed) : engine_(seed) {}
  double uniform(double lo, double hi) { return lo + (hi - lo) * (engine_() / 4294967296.0); }
  std::array<float, 3> point(double lo, double hi) {
    return {float(uniform(lo, hi)), float(uniform(lo, hi)), float(uniform(lo, hi))};
  }

 private:
  std::mt19937 engine_;
};

Point3 to_point(const std::array<float, 3>& f) { return {f[0], f[1], f[2]}; }
Point3 sub(const Point3& a, const Point3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Point3& a, const Point3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Point3 cross(const Point3& a, const Point3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double distance2(const Point3& a, const Point3& b) { return dot(sub(a, b), sub(a, b)); }

// An independent closest point: project onto the plane; inside → the projection, else the
// nearest of the three sides.
Point3 on_segment(const Point3& p, const Point3& a, const Point3& b) {
  const Point3 ab = sub(b, a);
  const double l2 = dot(ab, ab);
  const double t = l2 > 0 ? std::clamp(dot(sub(p, a), ab) / l2, 0.0, 1.0) : 0.0;
  return {a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]};
}
Point3 reference_closest(const Point3& p, const Point3& a, const Point3& b, const Point3& c) {
  const Point3 n = cross(sub(b, a), sub(c, a));
  const double n2 = dot(n, n);
  if (n2 > 1e-20) {
    const double s = dot(sub(p, a), n) / n2;
    const Point3 q{p[0] - s * n[0], p[1] - s * n[1], p[2] - s * n[2]};
    if (dot(cross(sub(b, a), sub(q, a)), n) >= 0 && dot(cross(sub(c, b), sub(q, b)), n) >= 0 &&
        dot(cross(sub(a, c), sub(q, c)), n) >= 0)
      return q;
  }
  Point3 best = on_segment(p, a, b);
  for (const Point3& q : {on_segment(p, b, c), on_segment(p, c, a)})
    if (distance2(p, q) < distance2(p, best)) best = q;
  return best;
}

TEST(EvalClosestPoint, MatchesAnIndependentConstructionOnRandomTriangles) {
  TestRandom random(7);
  for (int i = 0; i < 20000; ++i) {
    const Point3 a = to_point(random.point(-1, 1)), b = to_point(random.point(-1, 1)),
                 c = to_point(random.point(-1, 1)), p = to_point(random.point(-2, 2));
    const Point3 q = closest_point_on_triangle(p, a, b, c);
    const Point3 r = reference_closest(p, a, b, c);
    ASSERT_NEAR(std::sqrt(distance2(p, q)), std::sqrt(distance2(p, r)), 1e-12) << "case " << i;
    ASSERT_NEAR(std::sqrt(distance2(q, r)), 0.0, 1e-6) << "case " << i;
    // And no point of a 20 × 20 barycentric grid on the triangle is closer.
    if (i % 100 == 0)
      for (int u = 0; u <= 20; ++u)
        for (int v = 0; u + v <= 20; ++v) {
          const double s = u / 20.0, t = v / 20.0;
          const Point3 g{a[0] + s * (b[0] - a[0]) + t * (c[0] - a[0]),
                         a[1] + s * (b[1] - a[1]) + t * (c[1] - a[1]),
                         a[2] + s * (b[2] - a[2]) + t * (c[2] - a[2])};
          ASSERT_LE(distance2(p, q), distance2(p, g) + 1e-12);
        }
  }
}

TEST(EvalClosestPoint, DegenerateTrianglesActAsSegmentsAndPoints) {
  const Point3 a{0, 0, 0}, b{1, 0, 0}, c{2, 0, 0}, p{0.5, 1, 0};
  const Point3 q = closest_point_on_triangle(p, a, b, c);  // a segment from 0 to 2 on x
  EXPECT_NEAR(q[0], 0.5, 1e-15);
  EXPECT_NEAR(q[1], 0.0, 1e-15);
  const Point3 r = closest_point_on_triangle(p, b, b, b);
  EXPECT_EQ(r, b);
  const Point3 s = closest_point_on_triangle({3, 1, 0}, a, c, b);  // collinear, other order
  EXPECT_NEAR(std::sqrt(distance2({3, 1, 0}, s)), std::sqrt(2.0), 1e-15);
}

// A random triangle soup and a noisy quad grid (star-triangulated), as one triangle list.
std::vector<SurfaceTriangle> random_triangles(TestRandom& random, size_t soup) {
  std::vector<SurfaceTriangle> triangles;
  for (size_t i = 0; i < soup; ++i) {
    const auto a = random.point(-5, 5);
    auto near = [&] {
      return std::array<float, 3>{a[0] + float(random.uniform(-1, 1)),
                                  a[1] + float(random.uniform(-1, 1)),
                                  a[2] + float(random.uniform(-1, 1))};
    };
    triangles.push_back({a, near(), near(), uint32_t(i)});
  }
  test::Mesh grid = test::quad_grid(12, 9);
  for (size_t i = 0; i < grid.positions.size(); ++i)
    grid.positions[i] += float(random.uniform(-0.3, 0.3));
  for (SurfaceTriangle t : surface_triangles(grid.topology, grid.positions)) {
    t.face += uint32_t(soup);
    triangles.push_back(t);
  }
  return triangles;
}

TEST(EvalBvh, AnswersExactlyLikeBruteForce) {
  TestRandom random(11);
  for (size_t soup : {size_t{1}, size_t{7}, size_t{300}, size_t{3000}}) {
    const auto triangles = random_triangles(random, soup);
    const TriangleBvh bvh(triangles);
    ASSERT_EQ(bvh.triangle_count(), triangles.size());
    TriangleBvh::Cursor far_cursor, near_cursor;
    for (int i = 0; i < 2000; ++i) {
      const Point3 p = to_point(random.point(-8, 8));
      double best = std::numeric_limits<double>::infinity();
      for (const SurfaceTriangle& t : triangles)
        best = std::min(best, distance2(p, closest_point_on_triangle(
                                               p, to_point(t.a), to_point(t.b), to_point(t.c))));
      const TriangleBvh::Hit hit = bvh.closest(p);
      ASSERT_EQ(hit.squared_distance, best) << "soup " << soup << " query " << i;
      ASSERT_LT(hit.triangle, triangles.size());
      EXPECT_EQ(hit.face, triangles[hit.triangle].face);
      EXPECT_NEAR(distance2(p, hit.point), best, 1e-9);
      // A cursor changes nothing but speed: one carried over from far away queries,
      EXPECT_EQ(bvh.closest(p, far_cursor).squared_distance, best);
      // and one walking in small steps, which mostly skips the tree.
      for (int k = 0; k < 5; ++k) {
        const Point3 q{p[0] + 0.05 * k, p[1] - 0.03 * k, p[2] + 0.02 * k};
        double nearest = std::numeric_limits<double>::infinity();
        for (const SurfaceTriangle& t : triangles)
          nearest =
              std::min(nearest, distance2(q, closest_point_on_triangle(
                                                 q, to_point(t.a), to_point(t.b), to_point(t.c))));
        const TriangleBvh::Hit walked = bvh.closest(q, near_cursor);
        ASSERT_EQ(walked.squared_distance, nearest) << "soup " << soup << " walk " << i;
        ASSERT_LT(near_cursor.leaf, bvh.node_count());
      }
      // A bound below the answer finds nothing; one above finds the same.
      EXPECT_EQ(bvh.closest(p, best * 0.99).triangle, kNoIndex);
      EXPECT_EQ(bvh.closest(p, best * 1.01 + 1e-12).squared_distance, best);
    }
  }
}

TEST(EvalBvh, ManyTrianglesWithOneCentroidStayShallow) {
  // Every triangle has the same centroid: splits fall back to halving by count.
  std::vector<SurfaceTriangle> fan;
  for (uint32_t i = 0; i < 5000; ++i) {
    const float s = 1.0f + float(i);
    fan.push_back({{-s, 0, 0}, {s, 0, 0}, {0, 0, 0}, i});
  }
  const TriangleBvh bvh(fan);
  EXPECT_EQ(bvh.closest({0, 1, 0}).squared_distance, 1.0);
  EXPECT_EQ(bvh.closest({7000, 0, 2}).squared_distance, 2000.0 * 2000.0 + 4.0);
}

// Grid of nx × ny quads over [0, w] × [0, h] at height z.
test::Mesh grid_over(uint32_t nx, uint32_t ny, float w, float h, float z) {
  test::Mesh m = test::quad_grid(nx, ny);
  for (size_t v = 0; v < m.positions.size(); v += 3) {
    m.positions[v] = m.positions[v] * w / float(nx);
    m.positions[v + 1] = m.positions[v + 1] * h / float(ny);
    m.positions[v + 2] = z;
  }
  return m;
}

Result<HausdorffResult> measure(const test::Mesh& a, const test::Mesh& b,
                                const HausdorffOptions& options = {}) {
  return hausdorff(a.topology, a.positions, b.topology, b.positions, options);
}

TEST(EvalHausdorff, APlaneOffsetByDIsDBothWays) {
  //  B: 7 × 5 quads at z = 0.25 over the same 10 × 6 rectangle as A: 10 × 6 quads at z = 0.
  const test::Mesh a = grid_over(10, 6, 10, 6, 0), b = grid_over(7, 5, 10, 6, 0.25f);
  auto r = measure(a, b);
  ASSERT_TRUE(r.ok()) << r.message();
  for (const OneSidedDistance* d : {&r->a_to_b, &r->b_to_a}) {
    EXPECT_DOUBLE_EQ(d->max, 0.25);
    EXPECT_DOUBLE_EQ(d->mean, 0.25);
    EXPECT_DOUBLE_EQ(d->rms, 0.25);
  }
  EXPECT_DOUBLE_EQ(r->hausdorff, 0.25);
  EXPECT_DOUBLE_EQ(r->mean, 0.25);
  EXPECT_DOUBLE_EQ(r->rms, 0.25);
  EXPECT_NEAR(r->diagonal, std::sqrt(136.0), 1e-12);  // A's box: 10 × 6 × 0
  EXPECT_NEAR(r->percent(r->hausdorff), 100 * 0.25 / std::sqrt(136.0), 1e-12);

  HausdorffOptions original;
  original.reference_diagonal = 50;
  EXPECT_DOUBLE_EQ(measure(a, b, original)->percent(0.25), 0.5);
}

TEST(EvalHausdorff, APartOfAMeshIsAtDistanceZeroFromTheWhole) {
  //  A: 10 × 4 quads; B: its left half, 5 × 4, at the same positions.
  //  B → A is 0; A → B is the distance from A's right edge (x = 10) to B's (x = 5).
  const test::Mesh a = test::quad_grid(10, 4);
  test::Mesh b = a;
  b.topology.faces.clear();
  for (const Face& f : a.topology.faces) {
    float max_x = 0;
    for (uint32_t v : f.v) max_x = std::max(max_x, a.positions[3 * v]);
    if (max_x <= 5) b.topology.add_face(f);
  }
  auto r = measure(a, b);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_LT(r->b_to_a.max, 1e-12);  // samples on B lie on A, up to rounding
  EXPECT_LT(r->b_to_a.mean, 1e-12);
  EXPECT_DOUBLE_EQ(r->a_to_b.max, 5.0);  // a vertex sample sits on x = 10
  EXPECT_EQ(r->a_to_b.max_at[0], 10.0);
  EXPECT_NEAR(r->a_to_b.mean, 1.25, 0.05);  // half the area at 0, the other half 2.5 on average
  EXPECT_DOUBLE_EQ(r->hausdorff, 5.0);
}

TEST(EvalHausdorff, QuadsAreMeasuredAsFourTrianglesThroughTheirCentroid) {
  //  A non-planar quad (a saddle) against its own star triangulation:
  //   3-------2        3-------2
  //   |       |        | \   / |
  //   |       |   vs   |   4   |     4 = centroid = ((a + b + c + d) / 4 in double) as float
  //   |       |        | /   \ |
  //   0-------1        0-------1
  test::Mesh quad;
  quad.topology = Topology::with_vertices(4);
  quad.positions = {0, 0, 0.3f, 1, 0, -0.2f, 1.1f, 0.9f, 0.45f, 0, 1, -0.1f};
  quad.topology.add_quad(0, 1, 2, 3);
  test::Mesh star;
  star.topology = Topology::with_vertices(5);
  star.positions = quad.positions;
  for (int k = 0; k < 3; ++k) {
    double sum = 0;
    for (int v = 0; v < 4; ++v) sum += quad.positions[3 * v + k];
    star.positions.push_back(float(sum * 0.25));
  }
  for (uint32_t i = 0; i < 4; ++i) star.topology.add_triangle(i, (i + 1) % 4, 4);
  HausdorffOptions dense;
  dense.face_samples = 20000;
  auto same = measure(quad, star, dense);
  ASSERT_TRUE(same.ok()) << same.message();
  EXPECT_LT(same->hausdorff, 1e-12);

  // A diagonal split is another surface: the quad is not measured that way.
  test::Mesh split;
  split.topology = Topology::with_vertices(4);
  split.positions = quad.positions;
  split.topology.add_triangle(0, 1, 2);
  split.topology.add_triangle(0, 2, 3);
  auto other = measure(quad, split, dense);
  ASSERT_TRUE(other.ok()) << other.message();
  EXPECT_GT(other->hausdorff, 0.05);
}

TEST(EvalHausdorff, MixedTrianglesAndQuadsAgainstThemselvesAreZero) {
  const test::Mesh m = test::tri_quad_strip();
  auto r = measure(m, m);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_LT(r->hausdorff, 1e-12);
}

test::Mesh bumpy_sphere(uint32_t n, float bump) {
  // A latitude–longitude sphere of quads (triangles at the poles), with a wavy radius.
  test::Mesh m;
  m.topology = Topology::with_vertices(2 + n * (2 * n));
  auto add = [&](double theta, double phi) {
    const double r = 1 + bump * std::sin(5 * theta) * std::cos(3 * phi);
    m.positions.insert(m.positions.end(),
                       {float(r * std::sin(theta) * std::cos(phi)),
                        float(r * std::sin(theta) * std::sin(phi)), float(r * std::cos(theta))});
  };
  const double pi = std::acos(-1.0);
  add(0, 0);
  for (uint32_t i = 1; i <= n; ++i)
    for (uint32_t j = 0; j < 2 * n; ++j) add(pi * i / (n + 1), pi * j / n);
  add(pi, 0);
  auto ring = [&](uint32_t i, uint32_t j) { return 1 + (i - 1) * 2 * n + (j % (2 * n)); };
  for (uint32_t j = 0; j < 2 * n; ++j) {
    m.topology.add_triangle(0, ring(1, j), ring(1, j + 1));
    m.topology.add_triangle(m.topology.vertex_count - 1, ring(n, j + 1), ring(n, j));
    for (uint32_t i = 1; i < n; ++i)
      m.topology.add_quad(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j + 1));
  }
  return m;
}

TEST(EvalHausdorff, SameSeedSameResultOnAnyThreadCount) {
  const test::Mesh a = bumpy_sphere(40, 0.05f), b = bumpy_sphere(13, 0.0f);
  HausdorffOptions options;
  options.threads = 1;
  auto first = measure(a, b, options);
  ASSERT_TRUE(first.ok()) << first.message();
  for (unsigned threads : {1u, 2u, 3u, 8u}) {
    options.threads = threads;
    auto again = measure(a, b, options);
    ASSERT_TRUE(again.ok());
    for (auto [x, y] :
         {std::pair{&first->a_to_b, &again->a_to_b}, std::pair{&first->b_to_a, &again->b_to_a}}) {
      EXPECT_EQ(x->max, y->max) << threads << " threads";
      EXPECT_EQ(x->mean, y->mean) << threads << " threads";
      EXPECT_EQ(x->rms, y->rms) << threads << " threads";
      EXPECT_EQ(x->max_at, y->max_at) << threads << " threads";
      EXPECT_EQ(x->face_samples, y->face_samples) << threads << " threads";
      EXPECT_EQ(x->edge_samples, y->edge_samples) << threads << " threads";
    }
  }
  // Another seed gives other samples, and nearly the same numbers.
  options.seed = 99;
  auto other = measure(a, b, options);
  EXPECT_NE(other->a_to_b.mean, first->a_to_b.mean);
  EXPECT_NEAR(other->a_to_b.mean, first->a_to_b.mean, 0.02 * first->a_to_b.mean);
  EXPECT_NEAR(other->hausdorff, first->hausdorff, 0.05 * first->hausdorff);
}

TEST(EvalHausdorff, SampleCountsFollowTheOptions) {
  const test::Mesh a = bumpy_sphere(40, 0.05f), b = bumpy_sphere(13, 0.0f);
  auto r = measure(a, b);  // default: 10 per face of the larger mesh, on each surface
  ASSERT_TRUE(r.ok());
  const double expected = 10.0 * double(a.topology.faces.size());
  EXPECT_NEAR(double(r->a_to_b.face_samples), expected, 0.01 * expected);
  EXPECT_NEAR(double(r->b_to_a.face_samples), expected, 0.01 * expected);
  EXPECT_EQ(r->a_to_b.vertex_samples, a.topology.vertex_count);
  EXPECT_EQ(r->b_to_a.vertex_samples, b.topology.vertex_count);
  EXPECT_GT(r->a_to_b.edge_samples, 0u);

  HausdorffOptions faces_only;
  faces_only.face_samples = 5000;
  faces_only.sample_vertices = false;
  faces_only.sample_edges = false;
  auto f = measure(a, b, faces_only);
  EXPECT_NEAR(double(f->a_to_b.face_samples), 5000, 150);
  EXPECT_EQ(f->a_to_b.vertex_samples + f->a_to_b.edge_samples, 0u);
}

TEST(EvalHausdorff, InputErrorsAreStatusesNotCrashes) {
  const test::Mesh good = test::quad_grid(2, 2);
  test::Mesh bad = good;
  bad.topology.faces[1].v[2] = 99;
  EXPECT_NE(measure(good, bad).message().find("B: face 1 names vertex 99"), std::string::npos)
      << measure(good, bad).message();
  test::Mesh nan = good;
  nan.positions[4] = std::nanf("");
  EXPECT_NE(measure(nan, good).message().find("A: vertex 1 has a non-finite"), std::string::npos);
  test::Mesh empty = good;
  empty.topology.faces.clear();
  EXPECT_NE(measure(good, empty).message().find("no faces"), std::string::npos);
  EXPECT_FALSE(hausdorff(good.topology, std::span<const float>(good.positions).first(5),
                         good.topology, good.positions)
                   .ok());
}

TEST(EvalHausdorff, SurfacesWithoutAreaHaveVertexAndEdgeSamplesOnly) {
  //  A: two triangles squashed onto the segment 0–2 of the x axis; B: the unit square.
  test::Mesh flat;
  flat.topology = Topology::with_vertices(3);
  flat.positions = {0, 0, 0, 1, 0, 0, 2, 0, 0};
  flat.topology.add_triangle(0, 1, 2);
  flat.topology.add_triangle(2, 1, 0);
  auto r = measure(flat, test::quad_grid(1, 1));
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->a_to_b.face_samples, 0u);
  EXPECT_EQ(r->a_to_b.vertex_samples, 3u);
  EXPECT_DOUBLE_EQ(r->a_to_b.max, 1.0);    // vertex 2 is 1 from the square's corner (1, 0)
  EXPECT_GT(r->a_to_b.mean, 0.0);          // over the vertex samples, as nothing has area
  EXPECT_NEAR(r->b_to_a.max, 1.0, 1e-12);  // the square's corner (0, 1) is 1 from the segment
}

Frames frames_at_heights(const test::Mesh& m, std::initializer_list<float> heights) {
  Frames frames(m.topology.vertex_count);
  for (float z : heights) {
    std::vector<float> xyz = m.positions;
    for (size_t v = 2; v < xyz.size(); v += 3) xyz[v] = z;
    frames.add_step(std::move(xyz), frames.step_count());
  }
  return frames;
}

TEST(EvalHausdorffSteps, EachStepAgainstTheSameStepWithMeanAndMaxOverSteps) {
  const test::Mesh a = grid_over(6, 4, 6, 4, 0), b = grid_over(3, 2, 6, 4, 0);
  const Frames a_frames = frames_at_heights(a, {0, 1, 2});
  const Frames b_frames = frames_at_heights(b, {0.5f, 1, 2.25f});  // offsets 0.5, 0, 0.25
  std::vector<size_t> reported;
  StepsOptions options;
  options.progress = [&](size_t done, size_t total) {
    EXPECT_EQ(total, 3u);
    reported.push_back(done);
  };
  auto r = hausdorff_steps(a.topology, a_frames, b.topology, b_frames, options);
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_EQ(r->steps.size(), 3u);
  EXPECT_EQ(reported, (std::vector<size_t>{1, 2, 3}));
  EXPECT_DOUBLE_EQ(r->steps[0].hausdorff, 0.5);
  EXPECT_LT(r->steps[1].hausdorff, 1e-12);
  EXPECT_DOUBLE_EQ(r->steps[2].hausdorff, 0.25);
  EXPECT_DOUBLE_EQ(r->hausdorff.max, 0.5);
  EXPECT_NEAR(r->hausdorff.mean, 0.25, 1e-12);
  EXPECT_DOUBLE_EQ(r->rms.max, 0.5);
  // One diagonal for all steps: A's box over all steps (6 × 4 × 2).
  EXPECT_NEAR(r->diagonal, std::sqrt(56.0), 1e-12);
  for (const HausdorffResult& s : r->steps) EXPECT_EQ(s.diagonal, r->diagonal);

  // Step t equals hausdorff() on the two steps.
  auto direct = hausdorff(a.topology, a_frames.step(2), b.topology, b_frames.step(2));
  EXPECT_EQ(direct->a_to_b.mean, r->steps[2].a_to_b.mean);

  // A single step is compared with every step of the other side.
  const Frames one = frames_at_heights(a, {1});
  auto broadcast = hausdorff_steps(a.topology, one, b.topology, b_frames);
  ASSERT_TRUE(broadcast.ok()) << broadcast.message();
  ASSERT_EQ(broadcast->steps.size(), 3u);
  EXPECT_DOUBLE_EQ(broadcast->steps[0].hausdorff, 0.5);
  EXPECT_DOUBLE_EQ(broadcast->steps[2].hausdorff, 1.25);

  const Frames two = frames_at_heights(a, {0, 1});
  EXPECT_FALSE(hausdorff_steps(a.topology, two, b.topology, b_frames).ok());
}

// ---------------------------------------------------------------------------------------------
// The command line

test::CommandResult dynpm_cli(const std::string& arguments) {
  return test::run_command(std::string(DYNPM_CLI) + " " + arguments);
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The first number after "key": (or after "key": [ for an array), NaN if the key is missing.
double json_number(const std::string& json, const std::string& key) {
  size_t at = json.find("\"" + key + "\": ");
  if (at == std::string::npos) return std::nan("");
  at += key.size() + 4;
  if (json[at] == '[') ++at;
  return std::strtod(json.c_str() + at, nullptr);
}

TEST(EvalCli, HausdorffOfTwoMeshFilesAsTextAndJson) {
  test::TempDir dir;
  const test::Mesh a = grid_over(10, 6, 10, 6, 0), b = grid_over(7, 5, 10, 6, 0.25f);
  ASSERT_TRUE(write_mesh(dir.file("a.obj"), a.topology, a.positions).ok());
  ASSERT_TRUE(write_mesh(dir.file("b.ply"), b.topology, b.positions).ok());
  auto text = dynpm_cli("hausdorff " + dir.file("a.obj") + " " + dir.file("b.ply"));
  ASSERT_EQ(text.exit_code, 0) << text.output;
  EXPECT_TRUE(contains(text.output, "hausdorff")) << text.output;

  auto json = dynpm_cli("hausdorff --json --samples 5000 --seed 3 " + dir.file("a.obj") + " " +
                        dir.file("b.ply"));
  ASSERT_EQ(json.exit_code, 0) << json.output;
  for (const char* key : {"\"hausdorff_pct\"", "\"rms_pct\"", "\"mean_pct\"", "\"hausdorff\": 0.25",
                          "\"diagonal\"", "\"a_to_b_pct\"", "\"b_to_a_pct\"", "\"steps\": 1"})
    EXPECT_TRUE(contains(json.output, key)) << key << "\n" << json.output;
  EXPECT_FALSE(contains(json.output, "per_step")) << json.output;

  EXPECT_EQ(dynpm_cli("hausdorff " + dir.file("a.obj")).exit_code, 2);
  EXPECT_EQ(
      dynpm_cli("hausdorff --samples x " + dir.file("a.obj") + " " + dir.file("b.ply")).exit_code,
      2);
  EXPECT_EQ(dynpm_cli("hausdorff " + dir.file("a.obj") + " " + dir.file("none.obj")).exit_code, 1);
  EXPECT_EQ(dynpm_cli("hausdorff --help").exit_code, 0);
}

TEST(EvalCli, HausdorffOfTwoStepSequencesReportsEachStep) {
  const std::string dir = test::shared_data() + "/crashbox-s/obj";
  if (!std::filesystem::exists(dir)) GTEST_SKIP() << "no ../shared/data";
  // The crash box's first three steps against themselves, then step 0 against steps 0–2.
  const std::string steps = "'" + dir + "/frame_00[0-2].obj'";
  auto same = dynpm_cli("hausdorff --json --samples-per-face 2 " + steps + " " + steps);
  ASSERT_EQ(same.exit_code, 0) << same.output;
  EXPECT_TRUE(contains(same.output, "\"steps\": 3")) << same.output;
  EXPECT_LT(json_number(same.output, "hausdorff"), 1e-9) << same.output;
  EXPECT_TRUE(contains(same.output, "\"per_step\"")) << same.output;

  auto moving =
      dynpm_cli("hausdorff --json --samples-per-face 2 " + dir + "/frame_000.obj " + steps);
  ASSERT_EQ(moving.exit_code, 0) << moving.output;
  EXPECT_TRUE(contains(moving.output, "\"steps\": 3")) << moving.output;
  // Per step: step 0 against itself is 0; the tube then moves away from its rest state.
  const size_t per_step = moving.output.find("\"per_step\"");
  ASSERT_NE(per_step, std::string::npos) << moving.output;
  EXPECT_LT(json_number(moving.output.substr(per_step), "hausdorff_pct"), 1e-9) << moving.output;
  EXPECT_GT(json_number(moving.output, "hausdorff_pct"), 0.01) << moving.output;
}

// Steps as one result: maxima are the largest step's (with its place), means the mean of the
// steps' means, RMS values the root of the mean square, sample counts summed.
TEST(HausdorffSteps, AsOneResultCombinesTheSteps) {
  HausdorffSteps s;
  s.diagonal = 10;
  s.steps.resize(2);
  s.steps[0].a_to_b.max = 1, s.steps[0].a_to_b.mean = 0.5, s.steps[0].a_to_b.rms = 3;
  s.steps[0].a_to_b.max_at = {1, 2, 3};
  s.steps[1].a_to_b.max = 2, s.steps[1].a_to_b.mean = 1.5, s.steps[1].a_to_b.rms = 4;
  s.steps[1].a_to_b.max_at = {4, 5, 6};
  s.steps[0].b_to_a.max = 7, s.steps[1].b_to_a.max = 0.5;
  s.steps[0].a_to_b.face_samples = 10, s.steps[1].a_to_b.face_samples = 32;
  s.steps[0].mean = 1, s.steps[1].mean = 3;
  const HausdorffResult all = as_one_result(s);
  EXPECT_DOUBLE_EQ(all.diagonal, 10);
  EXPECT_DOUBLE_EQ(all.a_to_b.max, 2);
  EXPECT_EQ(all.a_to_b.max_at, (Point3{4, 5, 6}));
  EXPECT_DOUBLE_EQ(all.a_to_b.mean, 1);
  EXPECT_DOUBLE_EQ(all.a_to_b.rms, std::sqrt((9.0 + 16.0) / 2));
  EXPECT_EQ(all.a_to_b.face_samples, 42u);
  EXPECT_DOUBLE_EQ(all.b_to_a.max, 7);
  EXPECT_DOUBLE_EQ(all.hausdorff, 7);
  EXPECT_DOUBLE_EQ(all.mean, 2);
}

}  // namespace
}  // namespace dynpm
