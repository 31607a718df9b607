// The mean and RMS over every K-th area sample at scale (HausdorffOptions::mean_samples), and
// the searches that stop at the first triangle nearer than the maximum so far
// (TriangleBvh::closest(…, enough)), on the CalculiX crash box (shared data): the maxima and
// where they are must not move, below the limit the mean must be the one over every sample,
// and a search that stops early must never hide a closer triangle when it matters.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <random>

#include "dynpm/eval.h"
#include "dynpm/io.h"
#include "fixtures.h"

namespace dynpm {
namespace {

struct Step {
  Animation mesh;
  SurfaceTopology topology;
  Surface surface;
};

// On the heap: the surface points to its topology, which points to the mesh's.
std::unique_ptr<Step> crash_box_step(int step) {
  char name[32];
  std::snprintf(name, sizeof name, "/frame_%03d.obj", step);
  const std::string path = test::shared_data() + "/crashbox-s/obj" + name;
  if (!std::filesystem::exists(path)) return nullptr;
  auto s = std::make_unique<Step>();
  auto mesh = read_mesh(path);
  EXPECT_TRUE(mesh.ok()) << mesh.message();
  s->mesh = std::move(mesh).value();
  auto topology = prepare_topology("crash box", s->mesh.topology);
  EXPECT_TRUE(topology.ok()) << topology.message();
  s->topology = std::move(topology).value();
  auto surface = prepare_surface("crash box", s->topology, s->mesh.frames.step(0), 2);
  EXPECT_TRUE(surface.ok()) << surface.message();
  s->surface = std::move(surface).value();
  return s;
}

// The measurement with a zero node field on both sides: every sample then gets its exact
// closest point and the mean is over every area sample (fields turn the shortcuts off).
HausdorffResult every_sample_exact(const Step& a, const Step& b, const HausdorffOptions& options) {
  const std::vector<float> zero_a(a.mesh.topology.vertex_count, 0.0f),
      zero_b(b.mesh.topology.vertex_count, 0.0f);
  const FieldPair field{{FieldLocation::kNode, zero_a}, {FieldLocation::kNode, zero_b}};
  auto r = hausdorff(a.surface, b.surface, options, {&field, 1});
  EXPECT_TRUE(r.ok()) << r.message();
  return *r;
}

void expect_same_maxima(const HausdorffResult& x, const HausdorffResult& y) {
  EXPECT_EQ(x.hausdorff, y.hausdorff);
  for (auto [s, t] : {std::pair{&x.a_to_b, &y.a_to_b}, std::pair{&x.b_to_a, &y.b_to_a}}) {
    EXPECT_EQ(s->max, t->max);
    EXPECT_EQ(s->max_at, t->max_at);
    EXPECT_EQ(s->vertex_samples, t->vertex_samples);
    EXPECT_EQ(s->edge_samples, t->edge_samples);
    EXPECT_EQ(s->face_samples, t->face_samples);
  }
}

class EvalSampledMean : public ::testing::Test {
 protected:
  void SetUp() override {
    first_ = crash_box_step(0), last_ = crash_box_step(25);
    if (!first_ || !last_) GTEST_SKIP() << "../shared/data/crashbox-s is missing";
  }
  std::unique_ptr<Step> first_, last_;
};

TEST_F(EvalSampledMean, BelowTheLimitTheMeanIsOverEverySample) {
  // 29 k area samples a side, far below the default limit of 2^20: K = 1, and every value is
  // the one of the measurement where nothing is skipped, to the bit.
  HausdorffOptions options;
  const HausdorffResult fast = *hausdorff(first_->surface, last_->surface, options);
  const HausdorffResult exact = every_sample_exact(*first_, *last_, options);
  expect_same_maxima(fast, exact);
  EXPECT_EQ(fast.mean, exact.mean);
  EXPECT_EQ(fast.rms, exact.rms);
  EXPECT_EQ(fast.a_to_b.mean, exact.a_to_b.mean);
  EXPECT_EQ(fast.b_to_a.rms, exact.b_to_a.rms);
  // At the limit itself K is still 1; one sample over it, K = 2 and the mean moves.
  options.face_samples = 20000;
  options.mean_samples = 20000;
  const HausdorffResult at_limit = *hausdorff(first_->surface, last_->surface, options);
  const HausdorffResult all = every_sample_exact(*first_, *last_, options);
  EXPECT_EQ(at_limit.mean, all.mean);
  EXPECT_EQ(at_limit.rms, all.rms);
  options.mean_samples = 19999;
  const HausdorffResult over = *hausdorff(first_->surface, last_->surface, options);
  expect_same_maxima(over, all);
  EXPECT_NE(over.a_to_b.mean, all.a_to_b.mean);
  EXPECT_NEAR(over.a_to_b.mean, all.a_to_b.mean, 0.02 * all.a_to_b.mean);
}

TEST_F(EvalSampledMean, AStridedMeanKeepsTheMaximaAndEstimatesTheMean) {
  // Every 30th area sample in the mean (1,000 of 29 k); the others and the vertex and edge
  // samples searched only until a triangle nearer than the maximum so far. The maxima, where
  // they are and the sample counts must be those of the exact measurement; the mean and RMS
  // an estimate of the full ones; the same on any thread count.
  HausdorffOptions options;
  options.mean_samples = 1000;
  const HausdorffResult exact = every_sample_exact(*first_, *last_, options);
  HausdorffResult one_thread;
  for (unsigned threads : {1u, 2u, 3u}) {
    options.threads = threads;
    for (const auto& [a, b] : {std::pair{&first_, &last_}, std::pair{&last_, &first_}}) {
      const HausdorffResult r = *hausdorff((*a)->surface, (*b)->surface, options);
      const HausdorffResult e = a == &first_ ? exact : every_sample_exact(**a, **b, options);
      expect_same_maxima(r, e);
      for (auto [s, t] : {std::pair{&r.a_to_b, &e.a_to_b}, std::pair{&r.b_to_a, &e.b_to_a}}) {
        EXPECT_NE(s->mean, t->mean);
        EXPECT_NEAR(s->mean, t->mean, 0.1 * t->mean) << threads << " threads";
        EXPECT_NEAR(s->rms, t->rms, 0.1 * t->rms) << threads << " threads";
      }
    }
    const HausdorffResult r = *hausdorff(first_->surface, last_->surface, options);
    if (threads == 1) one_thread = r;
    EXPECT_EQ(r.mean, one_thread.mean) << threads << " threads";
    EXPECT_EQ(r.rms, one_thread.rms) << threads << " threads";
  }
}

TEST_F(EvalSampledMean, EnoughStopsAtANearerTriangleAndNeverHidesACloserOne) {
  // Points on the uncrushed box against the crushed one, in runs of neighbours as the samples
  // come. With `enough` (here the median squared distance) a query either proves it is below
  // it — its answer is a real triangle nearer than that — or returns the exact closest point.
  // Queries without `enough` on the same cursor stay exact after one that stopped early.
  const std::vector<SurfaceTriangle>& to = last_->surface.triangles;
  const TriangleBvh& bvh = last_->surface.bvh;
  const std::vector<SurfaceTriangle>& from = first_->surface.triangles;
  std::mt19937 engine(11);
  auto uniform = [&] { return engine() / 4294967296.0; };
  std::vector<Point3> points;
  for (size_t i = 0; i < from.size() && points.size() < 6000; i += 3)
    for (int k = 0; k < 3; ++k) {
      double u = uniform(), v = uniform();
      if (u + v > 1) u = 1 - u, v = 1 - v;
      const SurfaceTriangle& t = from[i];
      Point3 p;
      for (int c = 0; c < 3; ++c) p[c] = t.a[c] + u * (t.b[c] - t.a[c]) + v * (t.c[c] - t.a[c]);
      points.push_back(p);
    }
  std::vector<double> exact;
  for (const Point3& p : points) exact.push_back(bvh.closest(p).squared_distance);
  std::vector<double> sorted = exact;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double enough = sorted[sorted.size() / 2];
  ASSERT_GT(enough, 0);
  TriangleBvh::Cursor cursor;
  size_t stopped = 0, exact_anyway = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    const Point3& p = points[i];
    if (i % 5 == 4) {  // now and then a full query on the same cursor
      ASSERT_EQ(bvh.closest(p, cursor, false).squared_distance, exact[i]) << i;
      continue;
    }
    const TriangleBvh::Hit hit = bvh.closest(p, cursor, false, enough);
    ASSERT_NE(hit.triangle, kNoIndex);
    const SurfaceTriangle& t = to[hit.triangle];
    const Point3 q = closest_point_on_triangle(p, {t.a[0], t.a[1], t.a[2]},
                                               {t.b[0], t.b[1], t.b[2]}, {t.c[0], t.c[1], t.c[2]});
    const double d2 = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                      (p[2] - q[2]) * (p[2] - q[2]);
    ASSERT_EQ(hit.squared_distance, d2) << i;  // the distance to the triangle it names
    if (exact[i] < enough) {
      ASSERT_LT(hit.squared_distance, enough) << i;
      ASSERT_GE(hit.squared_distance, exact[i]) << i;
      stopped += hit.squared_distance > exact[i];
    } else {
      ASSERT_EQ(hit.squared_distance, exact[i]) << i;
      ++exact_anyway;
    }
  }
  EXPECT_GT(stopped, 20u);  // the early stop happened, and gave a farther triangle at times
  EXPECT_GT(exact_anyway, 1000u);
}

}  // namespace
}  // namespace dynpm
