// The shortcuts of `dynpm eval` at scale (issue 18), none of which may change a result.
//
// Space order: the samples of many jobs measured in the Morton order of their vertices, edges
// and triangles must give every number drawing order gives, to the bit.
//
// Samples spared a closest point: without fields, a vertex or edge
// sample nearer to its predecessor's closest triangle than the area samples' maximum cannot
// change any reported value, so it gets no query. These tests would fail if that shortcut ever
// changed a result: the same measurement with a field attached (every sample then gets its
// exact closest point) must give bit-identical distances, and a maximum that only a vertex
// sample reaches must still be found.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <random>

#include "dynpm/eval.h"
#include "fixtures.h"

namespace dynpm {
namespace {

struct Prepared {
  SurfaceTopology topology;
  Surface surface;
};

// On the heap: the surface points to its topology.
std::unique_ptr<Prepared> prepare(const test::Mesh& m) {
  auto p = std::make_unique<Prepared>();
  auto t = prepare_topology("mesh", m.topology);
  EXPECT_TRUE(t.ok()) << t.message();
  p->topology = std::move(t).value();
  auto s = prepare_surface("mesh", p->topology, m.positions, 2);
  EXPECT_TRUE(s.ok()) << s.message();
  p->surface = std::move(s).value();
  return p;
}

// An n × n quad grid over [0, 10]², z from `height`, with optional noise of amplitude `noise`.
test::Mesh plate(
    uint32_t n, double noise, uint32_t seed,
    double (*height)(double, double) = [](double, double) { return 0.0; }) {
  test::Mesh m = test::quad_grid(n, n);
  std::mt19937 engine(seed);
  for (size_t v = 0; v < m.positions.size(); v += 3) {
    const double x = m.positions[v] * 10.0 / n, y = m.positions[v + 1] * 10.0 / n;
    const double jitter = noise * (engine() / 4294967296.0 - 0.5);
    m.positions[v] = float(x), m.positions[v + 1] = float(y);
    m.positions[v + 2] = float(height(x, y) + jitter);
  }
  return m;
}

// A copy of m with its vertices and faces in a random order, as a level's are in progressive
// order: consecutive faces lie anywhere.
test::Mesh scrambled(const test::Mesh& m, uint32_t seed) {
  std::mt19937 engine(seed);
  std::vector<uint32_t> new_index(m.topology.vertex_count);
  std::iota(new_index.begin(), new_index.end(), 0u);
  std::shuffle(new_index.begin(), new_index.end(), engine);
  test::Mesh s = m;
  for (uint32_t v = 0; v < m.topology.vertex_count; ++v)
    for (int k = 0; k < 3; ++k) s.positions[3 * new_index[v] + k] = m.positions[3 * v + k];
  for (Face& f : s.topology.faces)
    for (int i = 0; i < f.degree(); ++i) f.v[i] = new_index[f.v[i]];
  std::shuffle(s.topology.faces.begin(), s.topology.faces.end(), engine);
  return s;
}

// Every distance of two measurements equal, to the bit, both ways: the maxima and where they
// are, the means, the RMS and the sample counts.
void expect_same_distances(const HausdorffResult& x, const HausdorffResult& y, unsigned threads) {
  EXPECT_EQ(x.hausdorff, y.hausdorff) << threads << " threads";
  EXPECT_EQ(x.mean, y.mean);
  EXPECT_EQ(x.rms, y.rms);
  for (auto [s, t] : {std::pair{&x.a_to_b, &y.a_to_b}, std::pair{&x.b_to_a, &y.b_to_a}}) {
    EXPECT_EQ(s->max, t->max) << threads << " threads";
    EXPECT_EQ(s->max_at, t->max_at) << threads << " threads";
    EXPECT_EQ(s->mean, t->mean);
    EXPECT_EQ(s->rms, t->rms);
    EXPECT_EQ(s->vertex_samples, t->vertex_samples);
    EXPECT_EQ(s->edge_samples, t->edge_samples);
    EXPECT_EQ(s->face_samples, t->face_samples);
  }
}

// The distances of A against B measured twice: as they are (vertex and edge samples may be
// skipped, and measured in space order from `space_order_triangles` on) and with a zero node
// field on both (nothing skipped, drawing order). Every value must be equal.
void expect_same_with_and_without_skipping(const test::Mesh& a, const test::Mesh& b,
                                           unsigned threads,
                                           size_t space_order_triangles = size_t{1} << 16) {
  const auto pa = prepare(a), pb = prepare(b);
  HausdorffOptions options;
  options.threads = threads;
  options.space_order_triangles = space_order_triangles;
  auto skipping = hausdorff(pa->surface, pb->surface, options);
  ASSERT_TRUE(skipping.ok()) << skipping.message();
  const std::vector<float> zero_a(a.topology.vertex_count, 0.0f),
      zero_b(b.topology.vertex_count, 0.0f);
  const FieldPair field{{FieldLocation::kNode, zero_a}, {FieldLocation::kNode, zero_b}};
  auto every_sample = hausdorff(pa->surface, pb->surface, options, {&field, 1});
  ASSERT_TRUE(every_sample.ok()) << every_sample.message();
  EXPECT_EQ(every_sample->fields.at(0).max, 0.0);
  expect_same_distances(*skipping, *every_sample, threads);
}

TEST(EvalSkippedSamples, ChangeNoDistanceOnNoisyPlates) {
  // A fine noisy plate against a coarse smooth one and the other way: maxima at vertices,
  // on edges and inside faces all occur among the samples.
  const auto wave = [](double x, double y) { return 0.4 * std::sin(x) * std::cos(0.7 * y); };
  const test::Mesh fine = plate(60, 0.05, 1, wave), coarse = plate(9, 0.0, 2, wave);
  for (unsigned threads : {1u, 2u, 3u}) {
    expect_same_with_and_without_skipping(fine, coarse, threads);
    expect_same_with_and_without_skipping(coarse, fine, threads);
  }
}

// Space order (HausdorffOptions::space_order_triangles) measures the samples of many jobs in
// the Morton order of their vertices, edges and triangles and counts them in drawing order:
// no number may differ from drawing order's, to the bit, on any thread count.
void expect_same_in_space_and_drawing_order(const test::Mesh& a, const test::Mesh& b,
                                            HausdorffOptions options) {
  const auto pa = prepare(a), pb = prepare(b);
  options.space_order_triangles = 0;  // always
  auto space = hausdorff(pa->surface, pb->surface, options);
  options.space_order_triangles = std::numeric_limits<size_t>::max();  // never
  auto drawing = hausdorff(pa->surface, pb->surface, options);
  ASSERT_TRUE(space.ok() && drawing.ok());
  expect_same_distances(*space, *drawing, options.threads);
}

TEST(EvalSpaceOrder, MeasuresAsDrawingOrderDoes) {
  // A fine noisy plate against a coarse one in scrambled order and back, with the mean over
  // every 9th area sample (so that the passes of the mean, of the other area samples and of
  // the vertices and edges all run), and with every sample in the mean.
  const auto wave = [](double x, double y) { return 0.4 * std::sin(x) * std::cos(0.7 * y); };
  const test::Mesh fine = plate(60, 0.05, 11, wave);
  const test::Mesh coarse = scrambled(plate(11, 0.0, 12, wave), 13);
  for (unsigned threads : {1u, 2u, 3u})
    for (uint64_t mean_samples : {uint64_t{4000}, uint64_t{0}}) {
      HausdorffOptions options;
      options.threads = threads;
      options.mean_samples = mean_samples;
      expect_same_in_space_and_drawing_order(fine, coarse, options);
      expect_same_in_space_and_drawing_order(coarse, fine, options);
    }
  // And against the measurement with a field, where nothing is skipped.
  expect_same_with_and_without_skipping(coarse, fine, 2, 0);
  expect_same_with_and_without_skipping(fine, coarse, 2, 0);
}

TEST(EvalSpaceOrder, AJobOfMoreSamplesThanABatchIsMeasuredAlone) {
  // One quad (four triangles, one job) holds all 600 k area samples of its side, more than a
  // batch of space order takes at once (2^19): that job is measured in drawing order.
  const test::Mesh fine = plate(12, 0.05, 14), quad = plate(1, 0.0, 15);
  HausdorffOptions options;
  options.face_samples = 600000;
  options.threads = 2;
  expect_same_in_space_and_drawing_order(quad, fine, options);
  // A large quad first and a fine plate after it in one surface: the first job (the quad's
  // four triangles and 192 small ones) draws 594 k samples and is measured alone; the small
  // jobs after it in the same batch are measured in space order, and each keeps its own tally.
  test::Mesh both = plate(1, 0.0, 16);
  for (size_t v = 0; v < both.positions.size(); v += 3)
    both.positions[v] *= 10, both.positions[v + 1] *= 10, both.positions[v + 2] = 3;
  const test::Mesh small = plate(60, 0.05, 17);
  const uint32_t offset = both.topology.vertex_count;
  both.positions.insert(both.positions.end(), small.positions.begin(), small.positions.end());
  for (Face f : small.topology.faces) {
    for (int i = 0; i < f.degree(); ++i) f.v[i] += offset;
    both.topology.faces.push_back(f);
  }
  both.topology.vertex_count += small.topology.vertex_count;
  expect_same_in_space_and_drawing_order(both, fine, options);
}

TEST(EvalSkippedSamples, AMaximumOnlyAVertexReachesIsFound) {
  // A flat plate with one raised vertex against a flat coarse plate: the largest distance is
  // exactly the spike's height, at the spike, and only its vertex sample reaches it.
  test::Mesh spiked = plate(40, 0.0, 3);
  const uint32_t spike = 20 * 41 + 17;
  spiked.positions[3 * spike + 2] = 0.75f;
  const test::Mesh flat = plate(5, 0.0, 4);
  const auto pa = prepare(spiked), pb = prepare(flat);
  auto r = hausdorff(pa->surface, pb->surface, HausdorffOptions{});
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->a_to_b.max, 0.75);
  const Point3 at{spiked.positions[3 * spike], spiked.positions[3 * spike + 1], 0.75};
  EXPECT_EQ(r->a_to_b.max_at, at);
  expect_same_with_and_without_skipping(spiked, flat, 2);
}

TEST(EvalBvh, EnoughTestsThePreviousAnswerFirst) {
  // closest(q, cursor, …, enough) tests the previous answer's triangle first: when it is nearer
  // than sqrt(enough) it is the hit, and otherwise the hit is a nearer triangle or the closest.
  const test::Mesh m = plate(20, 0.3, 5);
  const std::vector<SurfaceTriangle> triangles = surface_triangles(m.topology, m.positions);
  const TriangleBvh bvh(triangles, 1);
  TriangleBvh::Cursor cursor;
  std::mt19937 engine(6);
  auto coordinate = [&](double lo, double hi) {
    return lo + (hi - lo) * (engine() / 4294967296.0);
  };
  for (int i = 0; i < 500; ++i) {
    const Point3 p{coordinate(-1, 11), coordinate(-1, 11), coordinate(-2, 2)};
    const TriangleBvh::Hit previous = bvh.closest(p, cursor);
    const Point3 q{p[0] + coordinate(-0.5, 0.5), p[1] + coordinate(-0.5, 0.5), p[2]};
    const SurfaceTriangle& t = triangles[previous.triangle];
    const Point3 c = closest_point_on_triangle(q, {t.a[0], t.a[1], t.a[2]},
                                               {t.b[0], t.b[1], t.b[2]}, {t.c[0], t.c[1], t.c[2]});
    const double d2 = (q[0] - c[0]) * (q[0] - c[0]) + (q[1] - c[1]) * (q[1] - c[1]) +
                      (q[2] - c[2]) * (q[2] - c[2]);
    const double closest = bvh.closest(q).squared_distance;
    EXPECT_LE(closest, d2) << i;  // the previous answer's distance is an upper bound
    TriangleBvh::Cursor at = cursor;
    const TriangleBvh::Hit settled = bvh.closest(q, at, false, d2 * 1.000001);
    EXPECT_EQ(settled.triangle, previous.triangle) << i;
    EXPECT_EQ(settled.squared_distance, d2) << i;
    at = cursor;
    const TriangleBvh::Hit searched = bvh.closest(q, at, false, d2 * 0.999999);
    EXPECT_TRUE(searched.squared_distance < d2 * 0.999999 || searched.squared_distance == closest)
        << i;
  }
}

TEST(EvalBvh, ARefittedTreeAnswersLikeBruteForce) {
  const test::Mesh m = plate(16, 0.2, 7);
  TriangleBvh bvh(surface_triangles(m.topology, m.positions), 2);
  std::mt19937 engine(8);
  auto coordinate = [&](double lo, double hi) {
    return lo + (hi - lo) * (engine() / 4294967296.0);
  };
  // The plate bent a little more at every step until it curls up (every refitted answer is
  // exact), then crumpled, every vertex moved at random: then the boxes have grown too much
  // and the refit is refused.
  bool refused = false;
  for (int step = 1; step <= 7; ++step) {
    test::Mesh moved = m;
    for (size_t v = 0; v < moved.positions.size(); v += 3) {
      const double x = moved.positions[v];
      const double angle = 0.5 * std::min(step, 6) * x / 10.0;  // up to 3 rad
      moved.positions[v] = float(10.0 / (0.5 * std::min(step, 6)) * std::sin(angle));
      moved.positions[v + 2] += float(10.0 / (0.5 * std::min(step, 6)) * (1 - std::cos(angle)));
      if (step == 7)
        for (int k = 0; k < 3; ++k) moved.positions[v + k] += float(coordinate(-3, 3));
    }
    const std::vector<SurfaceTriangle> triangles =
        surface_triangles(moved.topology, moved.positions);
    if (!bvh.refit(triangles)) {
      refused = true;
      continue;
    }
    TriangleBvh::Cursor cursor;
    for (int i = 0; i < 300; ++i) {
      const Point3 p{coordinate(-2, 12), coordinate(-2, 12), coordinate(-2, 8)};
      double best = std::numeric_limits<double>::infinity();
      for (const SurfaceTriangle& t : triangles) {
        const Point3 q = closest_point_on_triangle(
            p, {t.a[0], t.a[1], t.a[2]}, {t.b[0], t.b[1], t.b[2]}, {t.c[0], t.c[1], t.c[2]});
        best = std::min(best, (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                                  (p[2] - q[2]) * (p[2] - q[2]));
      }
      ASSERT_EQ(bvh.closest(p).squared_distance, best) << "step " << step << " query " << i;
      ASSERT_EQ(bvh.closest(p, cursor).squared_distance, best) << "step " << step;
    }
  }
  EXPECT_TRUE(refused);  // only at the crumpled step
}

TEST(EvalHausdorff, UpdatedSurfacesMeasureLikeFreshOnes) {
  const auto wave = [](double x, double y) { return 0.4 * std::sin(x) * std::cos(0.7 * y); };
  const test::Mesh fine = plate(30, 0.05, 9, wave), coarse = plate(7, 0.0, 10, wave);
  auto fine_topology = prepare_topology("fine", fine.topology);
  auto coarse_topology = prepare_topology("coarse", coarse.topology);
  ASSERT_TRUE(fine_topology.ok() && coarse_topology.ok());
  Surface fine_step, coarse_step;
  fine_step.topology = &*fine_topology, coarse_step.topology = &*coarse_topology;
  for (int step = 0; step < 3; ++step) {
    test::Mesh a = fine, b = coarse;  // both lifted and sheared a little more at every step
    for (test::Mesh* m : {&a, &b})
      for (size_t v = 0; v < m->positions.size(); v += 3)
        m->positions[v + 2] += float(0.3 * step * std::sin(0.5 * m->positions[v] + step));
    ASSERT_TRUE(update_surface("fine", fine_step, a.positions, 2).ok());
    ASSERT_TRUE(update_surface("coarse", coarse_step, b.positions, 2).ok());
    auto updated = hausdorff(fine_step, coarse_step, HausdorffOptions{});
    const auto pa = prepare(a), pb = prepare(b);
    auto fresh = hausdorff(pa->surface, pb->surface, HausdorffOptions{});
    ASSERT_TRUE(updated.ok() && fresh.ok());
    EXPECT_EQ(updated->hausdorff, fresh->hausdorff) << "step " << step;
    EXPECT_EQ(updated->a_to_b.max_at, fresh->a_to_b.max_at);
    EXPECT_EQ(updated->b_to_a.max_at, fresh->b_to_a.max_at);
    EXPECT_DOUBLE_EQ(updated->mean, fresh->mean);
    EXPECT_DOUBLE_EQ(updated->rms, fresh->rms);
    EXPECT_EQ(updated->a_to_b.face_samples, fresh->a_to_b.face_samples);
  }
  // Bad positions are an error, as for prepare_surface().
  EXPECT_FALSE(update_surface("fine", fine_step, std::vector<float>(5, 0.0f)).ok());
}

}  // namespace
}  // namespace dynpm
