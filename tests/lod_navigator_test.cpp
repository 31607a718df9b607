// The stream-order Navigator's own loops (navigator.cpp): a split is learned from the faces the
// first time it is applied, then applied and undone by stores alone, with the faces ahead
// prefetched on meshes past the cache. Every level, reached split by split, in long jumps, and
// partly learned, holds exactly the faces apply_split() and undo_split() make.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <span>
#include <vector>

#include "crashbox_models.h"
#include "dynpm/lod.h"
#include "dynpm/pipeline.h"
#include "fixtures.h"

namespace dynpm {
namespace {

// apply_split()'s and undo_split()'s faces, to compare a navigator's with.
class Reference {
 public:
  explicit Reference(const ProgressiveMesh& m) : m_(m), faces_(m.base_faces) {
    faces_.resize(m.face_count_after(m.split_count()));
  }
  bool apply(uint32_t i) { return apply_split(m_, i, faces_, face_count_); }
  void undo(uint32_t i) { undo_split(m_, i, faces_, face_count_); }
  void reach(uint32_t k) {  // from the base mesh up to level k
    std::copy(m_.base_faces.begin(), m_.base_faces.end(), faces_.begin());
    face_count_ = m_.base_face_count;
    for (uint32_t i = 0; i < k; ++i) apply_split(m_, i, faces_, face_count_);
  }
  bool same(const Navigator& nav) const {
    return std::ranges::equal(nav.faces(), std::span(faces_.data(), face_count_));
  }

 private:
  const ProgressiveMesh& m_;
  std::vector<Face> faces_;
  uint32_t face_count_ = m_.base_face_count;
};

// A fresh navigator that learns in long jumps (beyond what it knows, back within it, then partly
// known and partly not), and each level compared.
void expect_jumps_are_what_apply_split_makes(const ProgressiveMesh& m) {
  const uint32_t splits = m.split_count();
  Reference ref(m);
  Navigator nav(m);
  for (uint32_t level : {splits / 3, splits / 7, splits / 2, splits / 2 + 1, splits, 0u, splits,
                         splits - splits / 5, 1u, splits / 4}) {
    ref.reach(level);
    nav.set_level(level);
    ASSERT_TRUE(ref.same(nav)) << "jumped to level " << level;
  }
}

// On the crash boxes' quads and triangles (80 KB of faces: no prefetches): level by level both
// ways, then long jumps on the navigator that learned every split, then a fresh one's.
TEST(Navigator, EveryLevelIsWhatApplySplitMakes) {
  for (const char* name : {"crashbox-mixed-5k", "crashbox-fields"}) {
    SCOPED_TRACE(name);
    DYNPM_CRASHBOX_OR_SKIP(model, name);
    const ProgressiveMesh& m = model->mesh;
    const uint32_t splits = m.split_count();
    Reference ref(m);
    Navigator nav(m);
    for (uint32_t k = 1; k <= splits; ++k) {
      ASSERT_TRUE(ref.apply(k - 1));
      nav.set_level(k);
      ASSERT_TRUE(ref.same(nav)) << "refined to level " << k;
    }
    for (uint32_t k = splits; k-- > 0;) {
      ref.undo(k);
      nav.set_level(k);
      ASSERT_TRUE(ref.same(nav)) << "coarsened to level " << k;
    }
    uint32_t jumps = 0;
    for (uint32_t k = splits; k > 0; k /= 3, ++jumps) {
      for (uint32_t level : {k, splits - k, splits, 0u, k / 2}) {
        ref.reach(level);
        nav.set_level(level);
        ASSERT_TRUE(ref.same(nav)) << "jumped to level " << level;
      }
    }
    EXPECT_GE(jumps, 7u);
    expect_jumps_are_what_apply_split_makes(m);
  }
}

// A wavy plate of 270 × 270 quads: 1.2 MB of faces, past the size below which the navigator
// does not prefetch, so these levels run the loops that do.
TEST(Navigator, JumpsOnAMeshPastTheCacheAreWhatApplySplitMakes) {
  test::Mesh plate = test::quad_grid(270, 270);
  for (size_t v = 0; v < plate.positions.size(); v += 3)
    plate.positions[v + 2] =
        std::sin(0.21f * plate.positions[v]) * std::cos(0.17f * plate.positions[v + 1]);
  const Animation a = plate.animation();
  auto m = build_progressive_mesh(a.topology, a.frames, BuildOptions{});
  ASSERT_TRUE(m.ok()) << m.message();
  ASSERT_GT(m->face_count_after(m->split_count()) * sizeof(Face), size_t{1} << 20);
  ASSERT_GT(m->split_count(), 70000u);
  expect_jumps_are_what_apply_split_makes(*m);
}

}  // namespace
}  // namespace dynpm
