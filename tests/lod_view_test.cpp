// The view-dependent request (docs/selective.md "View-dependent") on the CalculiX crash boxes
// (lossless builds): the spheres hold every final descendant of their split; after every
// re-target along a camera path the mesh is valid with the original's boundary loops, parts
// and components; every vertex in the frustum whose split's error projects above the tolerance
// exists, so near the eye the mesh is at full resolution where it matters; a camera looking away
// leaves the elsewhere level alone; and a budget stops the view's splits in order of screen
// error, passing the budget by at most one split's closure.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "crashbox_models.h"
#include "dynpm/lod.h"
#include "random_meshes.h"

namespace dynpm {
namespace {

using test::parts_shape;

std::array<double, 3> centre(const ProgressiveMesh& m) {
  return {(m.bbox_min[0] + m.bbox_max[0]) / 2, (m.bbox_min[1] + m.bbox_max[1]) / 2,
          (m.bbox_min[2] + m.bbox_max[2]) / 2};
}
double diagonal(const ProgressiveMesh& m) {
  double d = 0;
  for (int c = 0; c < 3; ++c)
    d += (m.bbox_max[c] - m.bbox_min[c]) * (m.bbox_max[c] - m.bbox_min[c]);
  return std::sqrt(d);
}

// A camera at `eye` looking at `at`, 700 pixels high, 900 wide, 35° (the viewer's).
ViewRequest camera(std::array<double, 3> eye, std::array<double, 3> at, double pixels,
                   uint64_t budget = 0) {
  ViewRequest v;
  v.eye = eye;
  v.at = at;
  v.up = {0, 1, 0};
  v.fov = 35;
  v.width = 900;
  v.height = 700;
  v.pixels = pixels;
  v.budget = budget;
  return v;
}

RefineTarget view_target(const ViewRequest& v) {
  RefineTarget r;
  r.kind = RefineTarget::Kind::kView;
  r.view = v;
  return r;
}

TEST(ViewRefine, ParsesTheCliSyntax) {
  const auto r = parse_refine_target(
      "view:EYE=1,2,3;AT=0,0,-1.5;UP=0,1,0;FOV=35;W=900;H=700;PX=0.5;BUDGET=2000");
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->kind, RefineTarget::Kind::kView);
  EXPECT_EQ(r->view.eye, (std::array<double, 3>{1, 2, 3}));
  EXPECT_EQ(r->view.at, (std::array<double, 3>{0, 0, -1.5}));
  EXPECT_EQ(r->view.up, (std::array<double, 3>{0, 1, 0}));
  EXPECT_EQ(r->view.fov, 35);
  EXPECT_EQ(r->view.width, 900);
  EXPECT_EQ(r->view.height, 700);
  EXPECT_EQ(r->view.pixels, 0.5);
  EXPECT_EQ(r->view.budget, 2000u);
  const auto d = parse_refine_target("view:EYE=1,0,0;AT=0,0,0;FOV=45;H=1080;PX=1");
  ASSERT_TRUE(d.ok()) << d.message();
  EXPECT_EQ(d->view.up, (std::array<double, 3>{0, 0, 1}));
  EXPECT_EQ(d->view.budget, 0u);
  for (const char* bad :
       {"view:EYE=1,0,0;AT=0,0,0;FOV=45;H=1080", "view:EYE=1,0,0;AT=1,0,0;FOV=45;H=9;PX=1",
        "view:EYE=1,0,0;AT=0,0,0;FOV=45;H=9;PX=0", "view:EYE=1,0,0;EYE=1,0,0",
        "view:EYE=1,0,0;AT=0,0,0;FOV=45;H=9;PX=1;BUDGET=1.5", "view:EYE"})
    EXPECT_FALSE(parse_refine_target(bad).ok()) << bad;
}

// Each split's sphere holds its new vertex, its parent, and the spheres of the later splits of
// either: by induction every final descendant.
TEST(ViewRefine, SpheresHoldEveryDescendant) {
  DYNPM_CRASHBOX_OR_SKIP(model, "crashbox-mixed-5k");
  const ProgressiveMesh& m = model->mesh;
  const uint32_t b = m.base_vertex_count, n = m.split_count();
  const double t = double(m.step_count() - 1), slack = 1e-5 * diagonal(m);
  const std::vector<float> s = split_spheres(m, t);
  auto holds = [&](uint32_t i, const float* p, double r) {
    const float* c = &s[size_t{i} * 4];
    const double d = std::hypot(double(p[0]) - c[0], double(p[1]) - c[1], double(p[2]) - c[2]);
    return d + r <= c[3] + slack;
  };
  // The last split (in stream order) of each vertex seen so far, from the top down.
  for (uint32_t i = 0; i < n; ++i) {
    ASSERT_TRUE(holds(i, &m.positions[size_t(t)][size_t{b + i} * 3], 0)) << i;
    ASSERT_TRUE(holds(i, &m.positions[size_t(t)][size_t{m.parent[i]} * 3], 0)) << i;
  }
  std::vector<uint32_t> next_of(m.vertex_count(), kNoIndex);  // the next split of a vertex
  for (uint32_t i = n; i-- > 0;) {
    for (uint32_t v : {b + i, m.parent[i]}) {
      if (const uint32_t j = next_of[v]; j != kNoIndex && j > i) {
        ASSERT_TRUE(holds(i, &s[size_t{j} * 4], s[size_t{j} * 4 + 3])) << i << " ⊇ " << j;
      }
    }
    next_of[m.parent[i]] = i;
  }
}

class ViewWalk {
 public:
  explicit ViewWalk(const ProgressiveMesh& m)
      : m_(m),
        deps_(derive_split_dependencies(m, test::test_reads())),
        targets_(m, deps_),
        nav_(m, deps_) {
    Navigator full(m);
    full.set_level(m.split_count());
    full_ = full.topology();
    original_ = parts_shape(full_);
  }

  // Re-targets to the view at step t; checks validity and the refinement's promise.
  void go(const ViewRequest& view, double t) {
    const ElsewhereLevel five = parse_elsewhere("5%").value();
    const RefineTarget target = view_target(view);
    auto wanted = targets_.request(five, std::span(&target, 1), t);
    ASSERT_TRUE(wanted.ok()) << wanted.message();
    nav_.set_active(*wanted);
    const SelectiveMesh mesh = nav_.active_mesh();
    test::expect_clean(mesh.topology, "view-refined");
    ASSERT_EQ(parts_shape(mesh.topology), original_);
    if (view.budget) return;
    // Every final vertex in the frustum whose split's error, seen from its own distance,
    // projects above the tolerance, exists (a point is a sphere of radius 0).
    const ViewFrustum frustum(view);
    const uint32_t b = m_.base_vertex_count;
    size_t seen = 0;
    for (uint32_t i = 0; i < m_.split_count(); ++i) {
      const auto p = position(b + i, t);
      const float point[4] = {p[0], p[1], p[2], 0};
      if (frustum.screen_error(point, m_.level_error(i)) > view.pixels) {
        ++seen;
        ASSERT_TRUE(nav_.split_active(i)) << "split " << i;
      }
    }
    last_seen_ = seen;
  }

  std::array<float, 3> position(uint32_t v, double t) const {
    const float* p = &m_.positions[size_t(t)][size_t{v} * 3];
    return {p[0], p[1], p[2]};
  }
  const SelectiveNavigator& nav() const { return nav_; }
  const RefineTargets& targets() const { return targets_; }
  const SplitDependencies& deps() const { return deps_; }
  size_t last_seen() const { return last_seen_; }

 private:
  const ProgressiveMesh& m_;
  SplitDependencies deps_;
  RefineTargets targets_;
  SelectiveNavigator nav_;
  Topology full_;
  test::PartsShape original_;
  size_t last_seen_ = 0;
};

// A camera orbits the crash box at three distances over a time sweep, then flies in close: every
// re-target is valid, the frustum's visible error is refined away.
TEST(ViewRefine, RetargetsAlongACameraPath) {
  for (const char* name : {"crashbox-mixed-5k", "crashbox-fields"}) {
    SCOPED_TRACE(name);
    DYNPM_CRASHBOX_OR_SKIP(model, name);
    const ProgressiveMesh& m = model->mesh;
    ViewWalk walk(m);
    const auto c = centre(m);
    const double d = diagonal(m);
    const uint32_t level = m.base_vertex_count + elsewhere_splits(m, parse_elsewhere("5%").value());
    const size_t last = m.step_count() - 1;
    int k = 0;
    for (double distance : {2.0, 1.0, 0.45})
      for (double angle = 0; angle < 6.28; angle += 1.1, ++k) {
        const double t = double((k * 7) % (last + 1));
        SCOPED_TRACE("distance " + std::to_string(distance) + ", angle " + std::to_string(angle));
        walk.go(camera({c[0] + distance * d * std::cos(angle), c[1] + 0.3 * d,
                        c[2] + distance * d * std::sin(angle)},
                       c, 1.0),
                t);
        EXPECT_GE(walk.nav().vertex_count(), level);
        EXPECT_LE(walk.nav().vertex_count(), m.full_vertex_count);
      }
    // Closer sees more: the same direction at decreasing distance.
    std::vector<uint32_t> counts;
    for (double distance : {3.0, 1.2, 0.5}) {
      walk.go(camera({c[0], c[1] + 0.2 * d, c[2] + distance * d}, c, 1.0), double(last));
      counts.push_back(walk.nav().vertex_count());
      std::cout << "[ view ] " << name << " at " << distance << " diagonals: " << counts.back()
                << " vertices (" << walk.last_seen() << " splits above 1 px)\n";
    }
    EXPECT_LT(counts[0], counts[1]);
    EXPECT_LT(counts[1], counts[2]);
    EXPECT_GT(walk.last_seen(), 100u) << "the close camera sees error above a pixel";
  }
}

// A camera outside the model looking away from it: nothing beyond the elsewhere level, and no
// split the view wants lies wholly behind an eye.
TEST(ViewRefine, NothingBehindTheCamera) {
  DYNPM_CRASHBOX_OR_SKIP(model, "crashbox-mixed-5k");
  const ProgressiveMesh& m = model->mesh;
  ViewWalk walk(m);
  const auto c = centre(m);
  const double d = diagonal(m);
  const uint32_t level = m.base_vertex_count + elsewhere_splits(m, parse_elsewhere("5%").value());
  const std::array<double, 3> eye = {c[0], c[1], c[2] + 0.8 * d}, away = {c[0], c[1], c[2] + 2 * d};
  walk.go(camera(eye, away, 0.1), 0);
  EXPECT_EQ(walk.nav().vertex_count(), level);
  EXPECT_EQ(walk.last_seen(), 0u);
  // Looking back at the model from the same place: a view inside the model's end sees some.
  const std::array<double, 3> inside = {c[0], c[1], c[2] + 0.1 * d};
  const ViewRequest half = camera(inside, {c[0] + d, c[1], c[2] + 0.1 * d}, 0.5);
  const auto wanted = walk.targets().view_splits(half, 0);
  const std::vector<float> s = split_spheres(m, 0);
  ASSERT_FALSE(wanted.empty());
  for (const auto& [error, i] : wanted) {
    const float* q = &s[size_t{i} * 4];
    EXPECT_GE(q[0] - inside[0], -double(q[3]) - 1e-6 * d)
        << "split " << i << " lies behind the eye";
  }
  walk.go(half, 0);
}

// With a budget the view's splits join by decreasing screen error until the vertices reach it:
// the result passes it by at most one split's closure, and holds every split above the first
// one it left out.
TEST(ViewRefine, BudgetIsRespectedUpToOneClosure) {
  for (const char* name : {"crashbox-mixed-5k", "crashbox-fields"}) {
    SCOPED_TRACE(name);
    DYNPM_CRASHBOX_OR_SKIP(model, name);
    const ProgressiveMesh& m = model->mesh;
    ViewWalk walk(m);
    const auto c = centre(m);
    const double d = diagonal(m);
    ViewRequest view = camera({c[0], c[1] + 0.2 * d, c[2] + 0.5 * d}, c, 0.5);
    walk.go(view, 0);
    const uint32_t unbounded = walk.nav().vertex_count();
    const ElsewhereLevel five = parse_elsewhere("5%").value();
    const uint32_t k = elsewhere_splits(m, five);
    const auto wanted = walk.targets().view_splits(view, 0);
    // The largest closure one split adds to the level.
    uint32_t largest = 0;
    std::vector<uint32_t> stack;
    for (const auto& [error, i] : wanted) {
      std::vector<uint8_t> prefix(m.split_count(), 0);
      std::fill_n(prefix.begin(), k, uint8_t{1});
      largest = std::max(largest, add_with_dependencies(walk.deps(), prefix, i, stack));
    }
    for (uint64_t budget : {uint64_t{m.base_vertex_count + k + 10},
                            uint64_t{(m.base_vertex_count + k + unbounded) / 2}, uint64_t{100}}) {
      SCOPED_TRACE("budget " + std::to_string(budget));
      view.budget = budget;
      walk.go(view, 0);
      const uint32_t n = walk.nav().vertex_count();
      std::cout << "[ view ] " << name << " budget " << budget << ": " << n
                << " vertices (unbounded " << unbounded << ", largest closure " << largest << ")\n";
      EXPECT_LT(n, std::max<uint64_t>(budget, m.base_vertex_count + k) + largest);
      EXPECT_LE(n, unbounded);
      if (budget < m.base_vertex_count + k) {
        EXPECT_EQ(n, m.base_vertex_count + k) << "a budget below the level adds nothing";
        continue;
      }
      EXPECT_GE(n, budget);
      size_t taken = 0;
      while (taken < wanted.size() && walk.nav().split_active(wanted[taken].second)) ++taken;
      ASSERT_LT(taken, wanted.size()) << "the budget left some out";
      EXPECT_GT(taken, 0u);
    }
  }
}

}  // namespace
}  // namespace dynpm
