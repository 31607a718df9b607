// The progressive mesh's round trip in tests: through the .dpm bytes and back, and the check
// that the fully refined navigator gives the input again (faces in the input's order and corner
// order, ids, times, and every position within the stated bound, bit-exact when lossless);
// faces as sets of input vertices, to compare meshes numbered differently.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <set>
#include <span>
#include <vector>

#include "dynpm/lod.h"
#include "dynpm/progressive.h"

namespace dynpm::test {

inline ProgressiveMesh through_file(const ProgressiveMesh& pm) {
  auto back = decode_dpm(encode_dpm(pm).value(), "memory.dpm");
  EXPECT_TRUE(back.ok()) << back.message();
  return std::move(back).value();
}

// `requested_bound` is BuildOptions::max_position_error, in bounding-box diagonals.
inline void expect_input_back(const Animation& a, const ProgressiveMesh& pm,
                              double requested_bound = 1.0 / (1 << 18)) {
  ASSERT_TRUE(pm.complete);
  Navigator nav(pm);
  nav.set_level(pm.split_count());
  auto o = original_order(nav);
  ASSERT_TRUE(o.ok()) << o.message();
  const Topology& t = o->topology;
  ASSERT_EQ(t.vertex_count, a.topology.vertex_count);
  ASSERT_EQ(t.faces.size(), a.topology.faces.size());
  for (size_t f = 0; f < t.faces.size(); ++f)
    ASSERT_EQ(t.faces[f], a.topology.faces[f]) << "face " << f;
  EXPECT_EQ(t.part_ids, a.topology.part_ids);
  EXPECT_EQ(t.element_ids, a.topology.element_ids);
  EXPECT_EQ(t.node_ids, a.topology.node_ids);
  ASSERT_EQ(pm.step_count(), a.step_count());
  std::vector<float> xyz(size_t{nav.vertex_count()} * 3);
  double worst = 0;
  for (size_t s = 0; s < a.step_count(); ++s) {
    EXPECT_EQ(pm.times[s], a.frames.step_time(s));
    nav.positions(double(s), xyz);
    const auto input = a.frames.step(s);
    for (uint32_t v = 0; v < t.vertex_count; ++v) {
      const float* p = &xyz[size_t{o->vertex_of_original[v]} * 3];
      const float* q = &input[size_t{v} * 3];
      if (pm.lossless) {
        ASSERT_EQ(std::memcmp(p, q, 12), 0) << "vertex " << v << " step " << s;
      } else {
        const double dx = double(p[0]) - q[0], dy = double(p[1]) - q[1], dz = double(p[2]) - q[2];
        worst = std::max(worst, std::sqrt(dx * dx + dy * dy + dz * dz));
      }
    }
  }
  if (!pm.lossless) {
    // The bound, plus the float32 rounding of the decoded value (half an ulp per coordinate).
    // The grid is at least 4 ulps of the largest coordinate (what float32 can hold there), so
    // the bound may exceed the requested one far from the origin.
    const double largest =
        std::max({std::abs(pm.bbox_min[0]), std::abs(pm.bbox_max[0]), std::abs(pm.bbox_min[1]),
                  std::abs(pm.bbox_max[1]), std::abs(pm.bbox_min[2]), std::abs(pm.bbox_max[2])});
    const double ulp = largest * std::ldexp(1.0, -23), sqrt3 = std::sqrt(3.0);
    EXPECT_LE(worst, pm.max_error + sqrt3 * ulp / 2);
    EXPECT_LE(pm.max_error, 1.01 * std::max(pm.diagonal() * requested_bound, 2 * sqrt3 * ulp));
  }
}

// Faces as sets of input vertex ids, for comparing meshes numbered differently.
inline std::multiset<std::vector<uint32_t>> face_sets(const Topology& t,
                                                      std::span<const uint32_t> to_input) {
  std::multiset<std::vector<uint32_t>> out;
  for (const Face& f : t.faces) {
    std::vector<uint32_t> s;
    for (uint32_t c : f.v)
      if (c != kNoVertex) s.push_back(to_input[c]);
    std::sort(s.begin(), s.end());
    out.insert(s);
  }
  return out;
}

// The split records and the attributes of two meshes are the same, array by array.
inline void expect_same_split_records(const ProgressiveMesh& a, const ProgressiveMesh& b) {
  EXPECT_EQ(a.parent, b.parent);
  EXPECT_EQ(a.error, b.error);
  EXPECT_EQ(a.wing_start, b.wing_start);
  ASSERT_EQ(a.wings.size(), b.wings.size());
  for (size_t k = 0; k < a.wings.size(); ++k) {
    EXPECT_EQ(a.wings[k].face, b.wings[k].face) << "wing " << k;
    EXPECT_EQ(a.wings[k].vertex, b.wings[k].vertex) << "wing " << k;
    EXPECT_EQ(a.wings[k].flags, b.wings[k].flags) << "wing " << k;
  }
  EXPECT_EQ(a.moved_start, b.moved_start);
  EXPECT_EQ(a.moved_faces, b.moved_faces);
  EXPECT_EQ(a.vertex_original_index, b.vertex_original_index);
  EXPECT_EQ(a.node_ids, b.node_ids);
  EXPECT_EQ(a.face_original_index, b.face_original_index);
  EXPECT_EQ(a.part_ids, b.part_ids);
  EXPECT_EQ(a.element_ids, b.element_ids);
}

}  // namespace dynpm::test
