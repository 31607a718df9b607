// order_splits_by_parent() (src/pipeline/split_order.h): the splits reordered within error bands
// so that parents ascend. On the hat-rail sample with errors spread over many bands: every split
// still applies with the reader's checks, the complete mesh is the same faces over the same
// original vertices, each level's stated error bounds the collapses it leaves in effect, the
// parents descend only a few times per band, and the input → progressive maps follow.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "dynpm/io.h"
#include "dynpm/pipeline.h"
#include "fixtures.h"
#include "pipeline/split_order.h"

namespace dynpm {
namespace {

ProgressiveMesh built_sample() {
  auto paths = expand_inputs(std::vector<std::string>{test::sample_dir() + "/frame_*.obj"});
  EXPECT_TRUE(paths.ok()) << paths.message();
  auto a = read_animation(*paths);
  EXPECT_TRUE(a.ok()) << a.message();
  auto pm = build_progressive_mesh(a->topology, a->frames, BuildOptions{});
  EXPECT_TRUE(pm.ok()) << pm.message();
  return std::move(pm).value();
}

// The faces after every split, each as its original index → its corners' original indices.
std::map<uint32_t, std::vector<uint32_t>> complete_faces(const ProgressiveMesh& pm) {
  std::vector<Face> faces = pm.base_faces;
  faces.resize(pm.full_face_count);
  uint32_t count = pm.base_face_count;
  for (uint32_t i = 0; i < pm.split_count(); ++i) {
    std::string problem;
    EXPECT_TRUE(apply_split(pm, i, faces, count, &problem)) << "split " << i << ": " << problem;
  }
  std::map<uint32_t, std::vector<uint32_t>> out;
  for (uint32_t f = 0; f < count; ++f) {
    auto& corners = out[pm.face_original_index[f]];
    for (uint32_t v : faces[f].v)
      if (v != kNoVertex) corners.push_back(pm.vertex_original_index[v]);
  }
  return out;
}

TEST(SplitOrder, ParentsAscendWithinBandsAndTheMeshAndTheErrorBoundsStay) {
  ProgressiveMesh before = built_sample();
  const uint32_t n = before.split_count();
  ASSERT_GT(n, 1000u);
  // Distinct errors, 1/64 octave apart (the build's are banded already): 16 per band.
  for (uint32_t i = 0; i < n; ++i) before.error[i] = std::ldexp(1.0f, -static_cast<int>(i / 64));
  for (uint32_t i = 0; i < n; ++i)
    before.error[i] *= std::exp2(-static_cast<float>(i % 64) / 64.0f);
  std::vector<uint32_t> new_vertex(before.full_vertex_count), new_face(before.full_face_count);
  for (uint32_t v = 0; v < new_vertex.size(); ++v) new_vertex[before.vertex_original_index[v]] = v;
  for (uint32_t f = 0; f < new_face.size(); ++f) new_face[before.face_original_index[f]] = f;

  ProgressiveMesh after = before;
  order_splits_by_parent(after, new_vertex, new_face);
  ASSERT_EQ(after.split_count(), n);
  EXPECT_NE(after.parent, before.parent);
  EXPECT_EQ(complete_faces(after), complete_faces(before));
  for (uint32_t v = 0; v < new_vertex.size(); ++v)
    ASSERT_EQ(after.vertex_original_index[new_vertex[v]], v);
  for (uint32_t f = 0; f < new_face.size(); ++f)
    ASSERT_EQ(after.face_original_index[new_face[f]], f);

  // Level k's stated error ≥ the error-order level that applied the splits up to the first one
  // level k lacks (the largest collapse error still in effect), and never increases.
  std::vector<uint32_t> original_split(n);  // new split → the error order's
  for (uint32_t v = before.base_vertex_count; v < before.full_vertex_count; ++v)
    original_split[new_vertex[before.vertex_original_index[v]] - before.base_vertex_count] =
        v - before.base_vertex_count;
  std::vector<char> applied(n, 0);
  uint32_t first_missing = 0, descents = 0;
  for (uint32_t k = 0; k < n; ++k) {
    applied[original_split[k]] = 1;
    while (first_missing < n && applied[first_missing]) ++first_missing;
    ASSERT_GE(after.level_error(k + 1), before.level_error(first_missing)) << "level " << k + 1;
    ASSERT_LE(after.level_error(k + 1), after.level_error(k)) << "level " << k + 1;
    // Within a band no farther than its width (2^(1/4)) from the error order's.
    ASSERT_LE(after.level_error(k + 1), before.level_error(k + 1) * std::exp2(0.25) * 1.0001);
    if (k > 0 && after.error[k] == after.error[k - 1] && after.parent[k] < after.parent[k - 1])
      ++descents;
  }
  // Sweeps of ascending parents: a few per band of 16 splits (error order descends at about
  // every other split on the crash data).
  EXPECT_LT(descents, n / 8) << "of " << n << " splits";
}

}  // namespace
}  // namespace dynpm
