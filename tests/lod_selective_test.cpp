// Selective refinement's core on the CalculiX crash boxes (lossless builds): the dependencies
// derived from the split records point backwards; a dependency-closed set of splits applied out
// of stream order leaves every face as the stream left it after its last applied writer; and
// random walks of region changes, growing and shrinking, keep the mesh valid with the
// original's boundary loops, parts and components.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <random>

#include "crashbox_models.h"
#include "dynpm/lod.h"
#include "dynpm/pipeline.h"
#include "fixtures.h"
#include "random_meshes.h"

namespace dynpm {
namespace {

using test::parts_shape;
using test::PartsShape;
using test::test_reads;

const char* const kBoxes[] = {"crashbox-mixed-5k", "crashbox-fields"};

// Every face's states in the stream: (writer split, the face right after it), writer order.
struct FaceHistory {
  std::vector<std::vector<std::pair<uint32_t, Face>>> states;

  explicit FaceHistory(const ProgressiveMesh& m) : states(m.face_count_after(m.split_count())) {
    Navigator nav(m);
    for (uint32_t i = 0; i < m.split_count(); ++i) {
      const uint32_t created = nav.face_count();
      nav.set_level(i + 1);
      const auto faces = nav.faces();
      auto record = [&](uint32_t f) { states[f].emplace_back(i, faces[f]); };
      for (uint32_t k = m.moved_start[i]; k < m.moved_start[i + 1]; ++k) record(m.moved_faces[k]);
      for (uint32_t k = m.wing_start[i]; k < m.wing_start[i + 1]; ++k)
        if (!m.wings[k].was_triangle()) record(m.wings[k].face);
      for (uint32_t f = created; f < nav.face_count(); ++f) record(f);
    }
  }
};

// Three wavy plates apart (33 k, 23 k and 15 k vertices): past the split count from which the
// fan and wing-edge rules replay groups of whole components on threads of their own (two groups
// here: the largest plate, and the other two). Any thread count gives one replay's result.
TEST(SplitDependencies, ComponentGroupsOnThreadsGiveOneReplaysResult) {
  const uint32_t sizes[] = {180, 150, 120};
  uint32_t total = 0;
  for (const uint32_t size : sizes) total += (size + 1) * (size + 1);
  test::Mesh plates;
  plates.topology = Topology::with_vertices(total);
  uint32_t first = 0;
  float x0 = 0;
  for (const uint32_t size : sizes) {
    const test::Mesh plate = test::quad_grid(size, size);
    for (size_t v = 0; v < plate.positions.size(); v += 3) {
      const float x = plate.positions[v], y = plate.positions[v + 1];
      plates.positions.insert(plates.positions.end(),
                              {x0 + x, y, std::sin(0.21f * x) * std::cos(0.17f * y)});
    }
    for (const Face& f : plate.topology.faces)
      plates.topology.add_quad(first + f.v[0], first + f.v[1], first + f.v[2], first + f.v[3]);
    first += plate.topology.vertex_count;
    x0 += float(size) + 10;
  }
  const Animation a = plates.animation();
  auto m = build_progressive_mesh(a.topology, a.frames, BuildOptions{});
  ASSERT_TRUE(m.ok()) << m.message();
  ASSERT_GT(m->split_count(), 1u << 16);  // kSplitsForGroups
  for (const SplitReads reads : {SplitReads::kFan, SplitReads::kWingEdges}) {
    const SplitDependencies one = derive_split_dependencies(*m, reads, 1);
    for (const unsigned threads : {2u, 3u}) {
      SCOPED_TRACE(std::to_string(threads) + " threads");
      const SplitDependencies grouped = derive_split_dependencies(*m, reads, threads);
      EXPECT_EQ(grouped.dep_start, one.dep_start);
      EXPECT_EQ(grouped.deps, one.deps);
      EXPECT_EQ(grouped.last_writer, one.last_writer);
      EXPECT_EQ(grouped.faces_after, one.faces_after);
    }
  }
}

TEST(SplitDependencies, PointToEarlierSplitsOnTheCrashBoxes) {
  for (const char* name : kBoxes) {
    SCOPED_TRACE(name);
    DYNPM_CRASHBOX_OR_SKIP(model, name);
    const ProgressiveMesh& m = model->mesh;
    const SplitDependencies deps = derive_split_dependencies(m);
    ASSERT_EQ(deps.split_count(), m.split_count());
    ASSERT_EQ(deps.faces_after.back(), m.face_count_after(m.split_count()));
    const uint32_t b = m.base_vertex_count;
    size_t with_none = 0;
    for (uint32_t i = 0; i < m.split_count(); ++i) {
      const auto d = deps.of(i);
      with_none += d.empty();
      for (size_t k = 0; k < d.size(); ++k) {
        ASSERT_LT(d[k], i) << "split " << i;
        if (k) {
          ASSERT_LT(d[k - 1], d[k]) << "split " << i << ": not ascending and unique";
        }
      }
      if (m.parent[i] >= b) {
        ASSERT_TRUE(std::binary_search(d.begin(), d.end(), m.parent[i] - b)) << "split " << i;
      }
    }
    // Splits late in the stream refine what earlier ones made: most need some.
    EXPECT_LT(with_none, m.split_count() / 2);
    std::cout << "[ dependencies ] " << name << ": " << m.split_count() << " splits, mean "
              << deps.mean_count() << ", max " << deps.max_count() << " per split\n";
    RecordProperty(std::string(name) + "_mean_deps", std::to_string(deps.mean_count()));
    RecordProperty(std::string(name) + "_max_deps", std::to_string(deps.max_count()));
  }
}

// The wing vertices a split names exist once its closure is applied: implied, not stored. Only
// a triangle wing names its vertex (the face it re-creates); a quad wing inserts v0 by slot and
// needs its face, not the split that made w (docs/selective.md "Narrower: what a wing reads").
TEST(SplitDependencies, ClosureHoldsTheTriangleWingsVertices) {
  DYNPM_CRASHBOX_OR_SKIP(model, "crashbox-mixed-5k");
  const ProgressiveMesh& m = model->mesh;
  const SplitDependencies deps = derive_split_dependencies(m);
  std::mt19937 rng(22);
  for (int trial = 0; trial < 200; ++trial) {
    const uint32_t i = std::uniform_int_distribution<uint32_t>(0, m.split_count() - 1)(rng);
    std::vector<uint8_t> set(m.split_count(), 0);
    set[i] = 1;
    close_under_dependencies(deps, set);
    for (uint32_t k = m.wing_start[i]; k < m.wing_start[i + 1]; ++k)
      if (m.wings[k].was_triangle() && m.wings[k].vertex >= m.base_vertex_count) {
        ASSERT_TRUE(set[m.wings[k].vertex - m.base_vertex_count]) << "split " << i;
      }
  }
}

// A random closed set: a prefix and the closure of a few random splits.
std::vector<uint8_t> random_closed_set(const SplitDependencies& deps, std::mt19937& rng) {
  const uint32_t n = deps.split_count();
  std::vector<uint8_t> set(n, 0);
  const uint32_t prefix = std::uniform_int_distribution<uint32_t>(0, n / 2)(rng);
  const int seeds = std::uniform_int_distribution<int>(0, 40)(rng);
  for (int s = 0; s < seeds; ++s) set[std::uniform_int_distribution<uint32_t>(0, n - 1)(rng)] = 1;
  close_under_dependencies(deps, set, prefix);
  return set;
}

// The fan rule's claim (docs/selective.md): out of order, every face is as the stream left it
// after its last writer in the set, and so is every split's input. Not so under the face
// creators (a face is as its applied writers make it): RandomClosedSetsStayValid checks those.
TEST(SelectiveNavigator, ClosedSetsLeaveEveryFaceAsTheStreamDid) {
  DYNPM_CRASHBOX_OR_SKIP(model, "crashbox-mixed-5k");
  const ProgressiveMesh& m = model->mesh;
  const SplitDependencies deps = derive_split_dependencies(m, SplitReads::kFan);
  const FaceHistory history(m);
  SelectiveNavigator nav(m, deps);
  std::mt19937 rng(7);
  for (int walk = 0; walk < 12; ++walk) {
    SCOPED_TRACE("set " + std::to_string(walk));
    const std::vector<uint8_t> set = random_closed_set(deps, rng);
    nav.set_active(set);
    const auto faces = nav.face_slots();
    for (uint32_t f = 0; f < faces.size(); ++f) {
      const auto& states = history.states[f];
      const Face* want = f < m.base_face_count ? &m.base_faces[f] : nullptr;
      for (const auto& [writer, state] : states)
        if (set[writer]) want = &state;
      ASSERT_EQ(nav.face_active(f), want != nullptr) << "face " << f;
      if (want) {
        ASSERT_EQ(faces[f], *want) << "face " << f;
      }
    }
  }
}

// The read sets under test here: the one named by DYNPM_SPLIT_READS (the face creators by
// default), and the fan, the first design.
const SplitReads kRules[] = {test_reads(), SplitReads::kFan};

// Random closed sets (a prefix and the closure of random splits, no region): the mesh is valid
// with the original's boundary loops, parts and components. Found what region walks did not:
// without the faces on the wing edges, the face creators' rule leaves inner vertices of valence 2.
TEST(SelectiveNavigator, RandomClosedSetsStayValid) {
  for (const char* name : kBoxes) {
    DYNPM_CRASHBOX_OR_SKIP(model, name);
    const ProgressiveMesh& m = model->mesh;
    Navigator full(m);
    full.set_level(m.split_count());
    const PartsShape original = parts_shape(full.topology());
    for (SplitReads reads : kRules) {
      SCOPED_TRACE(std::string(name) + ", read set " + std::to_string(int(reads)));
      const SplitDependencies deps = derive_split_dependencies(m, reads);
      SelectiveNavigator nav(m, deps);
      std::mt19937 rng(1997);
      for (int set = 0; set < 150; ++set) {
        const std::string what = "set " + std::to_string(set);
        nav.set_active(random_closed_set(deps, rng));
        const SelectiveMesh mesh = nav.active_mesh();
        test::expect_clean(mesh.topology, what);
        ASSERT_EQ(parts_shape(mesh.topology), original) << what;
      }
    }
  }
}

// Region changes as the viewer makes them: random boxes at random steps over random prefixes,
// growing, shrinking, jumping; after each one the mesh is valid, has the original's shape, and
// is the mesh a fresh navigator reaches directly.
TEST(SelectiveNavigator, RandomRegionWalksStayValid) {
  for (const auto& [name, reads] :
       {std::pair{kBoxes[0], kRules[0]}, std::pair{kBoxes[1], kRules[0]},
        std::pair{kBoxes[0], kRules[1]}, std::pair{kBoxes[1], kRules[1]}}) {
    SCOPED_TRACE(std::string(name) + ", read set " + std::to_string(int(reads)));
    DYNPM_CRASHBOX_OR_SKIP(model, name);
    const ProgressiveMesh& m = model->mesh;
    const SplitDependencies deps = derive_split_dependencies(m, reads);
    const RefineTargets targets(m, deps);
    Navigator full(m);
    full.set_level(m.split_count());
    const PartsShape original = parts_shape(full.topology());
    SelectiveNavigator nav(m, deps);
    std::mt19937 rng(2212);
    std::uniform_real_distribution<double> unit(0, 1);
    RefineTarget box;
    size_t grown = 0, shrunk = 0;
    for (int change = 0; change < 40; ++change) {
      const double t = std::uniform_int_distribution<size_t>(0, m.step_count() - 1)(rng);
      // A box around a random point of the bounding box, of random size; every 8th change the
      // whole mesh or nothing.
      for (int c = 0; c < 3; ++c) {
        const double lo = m.bbox_min[c], hi = m.bbox_max[c];
        const double mid = lo + unit(rng) * (hi - lo), half = unit(rng) * 0.4 * (hi - lo);
        box.box[c] = mid - half;
        box.box[c + 3] = mid + half;
      }
      if (change % 8 == 7) box.box = {1, 1, 1, 0, 0, 0};  // empty: parsed boxes never are
      ElsewhereLevel elsewhere;
      elsewhere.ratio = unit(rng) * 0.3;
      auto wanted = targets.request(elsewhere, std::span(&box, 1), t);
      ASSERT_TRUE(wanted.ok()) << wanted.message();
      const uint32_t before = nav.vertex_count();
      nav.set_active(*wanted);
      grown += nav.vertex_count() > before;
      shrunk += nav.vertex_count() < before;
      const std::string what = "change " + std::to_string(change) + " (" +
                               std::to_string(nav.vertex_count()) + " vertices)";
      const SelectiveMesh mesh = nav.active_mesh();
      test::expect_clean(mesh.topology, what);
      ASSERT_EQ(parts_shape(mesh.topology), original) << what;
      SelectiveNavigator fresh(m, deps);
      fresh.set_active(*wanted);
      ASSERT_EQ(fresh.active_mesh().topology.faces, mesh.topology.faces) << what;
    }
    EXPECT_GT(grown, 5u);
    EXPECT_GT(shrunk, 5u);
  }
}

}  // namespace
}  // namespace dynpm
