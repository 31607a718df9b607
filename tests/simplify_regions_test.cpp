// Regions (docs/simplify.md "Regions"): a mesh of one large component, simplified to a stop, is
// cut by space into regions that collapse on any free thread with the corners of faces across a
// cut frozen, then one queue goes on. The result must not depend on the thread count, meet the
// target exactly, stay valid after every round and every collapse, keep each region's collapses
// inside it, and lose nothing measurable against the one queue.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <vector>

#include "core/components.h"
#include "crash_box.h"
#include "dynpm/eval.h"
#include "dynpm/simplify.h"
#include "fixtures.h"
#include "simplify/collapse_mesh.h"
#include "simplify/regions.h"

namespace dynpm {
namespace {

using test::crashbox;
using test::Told;

SimplifyOptions region_options(unsigned threads) {
  SimplifyOptions o;
  o.key_steps = {0, 12, 25};
  o.region_min_vertices = 0;  // regions on the small crash box too
  o.threads = threads;
  return o;
}

// What a told collapse did to the faces.
void replay(std::vector<Face>& faces, const Told::Collapse& c) {
  CollapseRecord record;
  record.v0 = c.v0, record.v1 = c.v1, record.moved_faces = c.moved;
  for (size_t w = 0; w < c.wings.size(); w += 3)
    record.wings[record.wing_count++] = {c.wings[w], c.wings[w + 1],
                                         static_cast<uint8_t>(c.wings[w + 2])};
  simplification::collapse_faces(faces, record);
}

// The three stops: a vertex ratio, a face count, a maximum error.
void set_stop(SimplifyOptions& o, int stop) {
  if (stop == 0) o.target_ratio = 0.25;
  if (stop == 1) o.target_faces = 400;
  if (stop == 2) o.max_error = 0.004;
}

TEST(Regions, TheSameCollapsesAndMeshOnAnyThreadCountAndTheTargetExact) {
  const Animation* box = crashbox();
  ASSERT_NE(box, nullptr);
  const uint32_t n = box->topology.vertex_count;
  for (int stop = 0; stop < 3; ++stop) {
    SCOPED_TRACE(stop);
    Told first;
    Topology first_mesh;
    for (unsigned threads : {1u, 2u, 3u, 8u}) {
      SimplifyOptions o = region_options(threads);
      set_stop(o, stop);
      Told told;
      auto r = simplify(box->topology, box->frames, o, &told);
      ASSERT_TRUE(r.ok()) << r.message();
      EXPECT_EQ(r->regions, size_t{1} << simplification::kRegionLevels);
      EXPECT_TRUE(r->target_reached) << r->stop_reason;
      EXPECT_EQ(r->collapses, told.collapses.size());
      EXPECT_EQ(r->topology.vertex_count, n - told.collapses.size());
      // The regions made a good part of the collapses (on this small box 29 % of the vertices
      // are frozen, and each keeps a collapse and two faces for the one queue), the one queue
      // the rest.
      EXPECT_GT(r->region_collapses, r->collapses / 4);
      EXPECT_LT(r->region_collapses, r->collapses);
      if (stop == 0) {
        EXPECT_EQ(r->topology.vertex_count, uint32_t(std::ceil(0.25 * n)));
      } else if (stop == 1) {
        // As one queue stops: the collapse that reaches the target may remove two triangles.
        EXPECT_LE(r->topology.faces.size(), 400u);
        EXPECT_GE(r->topology.faces.size(), 397u);
      } else {
        for (const Told::Collapse& c : told.collapses)
          EXPECT_LE(static_cast<float>(c.error), 0.004f);
      }
      if (threads == 1) {
        first = told, first_mesh = r->topology;
        continue;
      }
      EXPECT_TRUE(told.collapses == first.collapses) << threads << " threads";
      EXPECT_EQ(r->topology.faces, first_mesh.faces) << threads << " threads";
    }
  }
}

// Test mode checks the whole mesh after every round of the regions and every collapse of the one
// queue; the told collapses, replayed on the input's faces, give the result.
TEST(Regions, EveryRoundAndCollapseLeavesAValidMeshAndTheToldOnesGiveTheResult) {
  const Animation* box = crashbox();
  ASSERT_NE(box, nullptr);
  for (int stop = 0; stop < 3; ++stop) {
    SCOPED_TRACE(stop);
    SimplifyOptions o = region_options(2);
    o.check_every_collapse = true;
    set_stop(o, stop);
    Told told;
    auto r = simplify(box->topology, box->frames, o, &told);
    ASSERT_TRUE(r.ok()) << r.message();
    std::vector<Face> faces = box->topology.faces;
    for (const Told::Collapse& c : told.collapses) replay(faces, c);
    std::vector<uint32_t> original;
    const Topology replayed = simplification::live_topology(box->topology, faces, original);
    EXPECT_EQ(replayed.faces, r->topology.faces);
    EXPECT_EQ(original, r->original_vertex);
  }
}

// The regions' collapses come first in the told order; none moves or keeps a corner of a face
// across a cut, and every face it changes lies in the region of its two ends.
TEST(Regions, EachRegionsCollapsesStayInsideItAndOffTheBorders) {
  const Animation* box = crashbox();
  ASSERT_NE(box, nullptr);
  const Topology& input = box->topology;
  SimplifyOptions o = region_options(2);
  set_stop(o, 0);
  Told told;
  auto r = simplify(input, box->frames, o, &told);
  ASSERT_TRUE(r.ok()) << r.message();
  // The simplifier cuts at the first key step, step 0 here.
  const auto step0 = box->frames.step(0);
  const std::vector<uint16_t> region_of =
      simplification::spatial_regions(input, step0.data(), 3, simplification::kRegionLevels);
  std::vector<uint32_t> in_region(size_t{1} << simplification::kRegionLevels, 0);
  for (uint32_t v = 0; v < input.vertex_count; ++v) ++in_region[region_of[v]];
  for (uint32_t count : in_region)  // median cuts: equal halves, to one vertex
    EXPECT_NEAR(double(count), double(input.vertex_count) / in_region.size(), 4.0);
  size_t components = 0;
  const std::vector<uint32_t> component = connected_components(input, components);
  const std::vector<uint8_t> frozen =
      simplification::frozen_borders(input, region_of, component, components);
  const size_t frozen_count = std::count(frozen.begin(), frozen.end(), uint8_t{1});
  EXPECT_GT(frozen_count, 0u);
  EXPECT_LT(frozen_count, input.vertex_count / 2);
  std::vector<Face> faces = input.faces;  // replayed, to see the faces each collapse changes
  ASSERT_LE(r->region_collapses, told.collapses.size());
  for (size_t k = 0; k < r->region_collapses; ++k) {
    const Told::Collapse& c = told.collapses[k];
    ASSERT_FALSE(frozen[c.v0] || frozen[c.v1]) << "collapse " << k;
    ASSERT_EQ(region_of[c.v0], region_of[c.v1]) << "collapse " << k;
    for (uint32_t f : c.moved)
      for (uint32_t corner : faces[f].v) {
        if (corner == kNoVertex) continue;
        ASSERT_EQ(region_of[corner], region_of[c.v0]) << "collapse " << k;
      }
    replay(faces, c);
  }
  // The one queue took the frozen corners on: some of them are gone.
  size_t frozen_removed = 0;
  for (size_t k = r->region_collapses; k < told.collapses.size(); ++k)
    frozen_removed += frozen[told.collapses[k].v0];
  EXPECT_GT(frozen_removed, frozen_count / 4);
}

// A component across a cut with fewer than five frozen corners is frozen whole (its live count,
// which (P3) reads, is written by several regions).
TEST(Regions, ASmallComponentAcrossACutIsFrozenWhole) {
  test::Mesh strip = test::quad_grid(4, 1);  // 10 vertices, one component
  test::Mesh sheet = test::quad_grid(4, 4);  // 25 vertices
  Topology both = Topology::with_vertices(35);
  for (const Face& f : strip.topology.faces) both.add_face(f, 0);
  for (Face f : sheet.topology.faces) {
    for (uint32_t& c : f.v)
      if (c != kNoVertex) c += 10;
    both.add_face(f, 1);
  }
  std::vector<uint16_t> region_of(35, 0);
  for (uint32_t i = 0; i < 5; ++i)
    region_of[i] = region_of[5 + i] = i >= 3;  // strip: cut at x = 2.5
  for (uint32_t j = 0; j < 5; ++j)
    for (uint32_t i = 0; i < 5; ++i) region_of[10 + j * 5 + i] = i >= 3;  // sheet: the same cut
  size_t components = 0;
  const std::vector<uint32_t> component = connected_components(both, components);
  ASSERT_EQ(components, 2u);
  const std::vector<uint8_t> frozen =
      simplification::frozen_borders(both, region_of, component, components);
  for (uint32_t v = 0; v < 10; ++v) EXPECT_EQ(frozen[v], 1) << v;  // 4 corners across: all of it
  for (uint32_t j = 0; j < 5; ++j)
    for (uint32_t i = 0; i < 5; ++i)
      EXPECT_EQ(frozen[10 + j * 5 + i], i == 2 || i == 3) << i << ", " << j;  // 10 across
}

// A bumpy sheet of 256 × 256 quads (66,049 vertices, one component: regions by default), its
// height a sum of waves of several lengths, so that collapses cost differently everywhere.
test::Mesh bumpy_sheet() {
  test::Mesh m = test::quad_grid(256, 256);
  for (size_t v = 0; v < m.positions.size(); v += 3) {
    const float x = m.positions[v], y = m.positions[v + 1];
    m.positions[v + 2] = 6 * std::sin(x / 23) * std::cos(y / 31) + 2 * std::sin((x + 2 * y) / 7) +
                         0.5f * std::cos(x * y / 400);
  }
  return m;
}

// Against the one queue on the same mesh: the same vertex count, a largest collapse error within
// a few percent and a Hausdorff distance (measured with the input as A) no larger than 5 % more;
// with half-edge placement to 25 % and 1 %, with optimal placement (no listener) to 25 %.
TEST(Regions, KeepTheOneQueuesQuality) {
  const test::Mesh sheet = bumpy_sheet();
  const Animation a = sheet.animation();
  for (int run = 0; run < 3; ++run) {
    SCOPED_TRACE(run);
    SimplifyOptions o;
    o.target_ratio = run == 1 ? 0.01 : 0.25;
    if (run == 2) o.placement = Placement::kOptimal;
    SimplifyOptions whole = o;
    whole.region_min_vertices = UINT32_MAX;
    auto regions = simplify(a.topology, a.frames, o);
    auto one_queue = simplify(a.topology, a.frames, whole);
    ASSERT_TRUE(regions.ok() && one_queue.ok());
    ASSERT_EQ(regions->regions, size_t{1} << simplification::kRegionLevels);
    ASSERT_EQ(one_queue->regions, 0u);
    EXPECT_GT(regions->region_collapses, regions->collapses * 3 / 4);
    EXPECT_EQ(regions->topology.vertex_count, one_queue->topology.vertex_count);
    EXPECT_LE(regions->max_error, 1.05 * one_queue->max_error);
    auto distance = [&](const SimplifyResult& s) {
      std::vector<float> xyz;
      for (uint32_t v : s.original_vertex)
        xyz.insert(xyz.end(), &sheet.positions[v * 3], &sheet.positions[v * 3] + 3);
      const auto& at = s.key_step_positions.empty() ? xyz : s.key_step_positions[0];
      return hausdorff(a.topology, sheet.positions, s.topology, at)->hausdorff;
    };
    const double ours = distance(*regions), theirs = distance(*one_queue);
    std::printf("%s to %.0f %%: Hausdorff %.5g with regions, %.5g with one queue\n",
                run == 2 ? "optimal" : "half-edge", 100 * *o.target_ratio, ours, theirs);
    EXPECT_LE(ours, 1.05 * theirs);
  }
}

// Optimal placement moves v1 within its region: without a listener the regions run, the same
// mesh and positions on any thread count, the target exact (quality: KeepTheOneQueuesQuality).
// With a listener (whose records would need the moved positions) they do not.
TEST(Regions, OptimalPlacementWithoutAListener) {
  const Animation* box = crashbox();
  ASSERT_NE(box, nullptr);
  std::optional<SimplifyResult> first;
  for (unsigned threads : {1u, 2u, 8u}) {
    SimplifyOptions o = region_options(threads);
    o.key_steps.clear();  // every step: optimal placement moves v1 in each
    o.placement = Placement::kOptimal;
    o.target_ratio = 0.25;
    auto r = simplify(box->topology, box->frames, o);
    ASSERT_TRUE(r.ok()) << r.message();
    EXPECT_EQ(r->regions, size_t{1} << simplification::kRegionLevels);
    EXPECT_EQ(r->topology.vertex_count, uint32_t(std::ceil(0.25 * box->topology.vertex_count)));
    if (!first) {
      first = std::move(r).value();
      continue;
    }
    EXPECT_EQ(r->topology.faces, first->topology.faces) << threads << " threads";
    EXPECT_EQ(r->key_step_positions, first->key_step_positions) << threads << " threads";
  }
  SimplifyOptions told = region_options(2);
  told.key_steps.clear();
  told.placement = Placement::kOptimal;
  told.target_ratio = 0.25;
  Told listener;
  auto r = simplify(box->topology, box->frames, told, &listener);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->regions, 0u);
}

// Regions only where the options allow them: not without a stop (a build runs to the end), not
// with independent rounds, not below region_min_vertices, and not where islands of whole
// components share the work (no component holds a quarter of the vertices).
TEST(Regions, OnlyWithAStopAndOneLargeComponent) {
  const Animation* box = crashbox();
  ASSERT_NE(box, nullptr);
  SimplifyOptions to_the_end = region_options(2);
  auto r = simplify(box->topology, box->frames, to_the_end);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->regions, 0u);
  SimplifyOptions rounds = region_options(2);
  set_stop(rounds, 0);
  rounds.independent_rounds = 0.05;
  r = simplify(box->topology, box->frames, rounds);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->regions, 0u);
  SimplifyOptions small = region_options(2);
  set_stop(small, 0);
  small.region_min_vertices = box->topology.vertex_count + 1;
  r = simplify(box->topology, box->frames, small);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->regions, 0u);
  // Five sheets of a fifth each: islands, not regions.
  Topology sheets = Topology::with_vertices(5 * 121);
  std::vector<float> xyz;
  const test::Mesh grid = test::quad_grid(10, 10);
  for (uint32_t k = 0; k < 5; ++k) {
    for (Face f : grid.topology.faces) {
      for (uint32_t& c : f.v)
        if (c != kNoVertex) c += 121 * k;
      sheets.add_face(f, static_cast<int32_t>(k));
    }
    for (size_t i = 0; i < grid.positions.size(); ++i)
      xyz.push_back(grid.positions[i] + (i % 3 == 0 ? 20.0f * k : 0.0f) +
                    (i % 3 == 2 ? 0.1f * std::sin(float(i)) : 0.0f));
  }
  Frames frames;
  frames.set_vertex_count(sheets.vertex_count);
  frames.add_step(xyz, 0);
  SimplifyOptions parts;
  parts.region_min_vertices = 0;
  parts.island_min_vertices = 0;
  parts.target_ratio = 0.5;
  r = simplify(sheets, frames, parts);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->regions, 0u);
  EXPECT_EQ(r->islands, 5u);
  EXPECT_EQ(island_vertex_counts(sheets, parts).size(), 5u);  // what a memory estimate is told
}

// One large component beside small ones (the dragon's case): regions with a stop, and then no
// islands for a memory estimate (the regions hold every vertex's quadrics); islands to the end.
TEST(Regions, OneLargeComponentBesideSmallOnes) {
  const test::Mesh sheet = bumpy_sheet();
  const test::Mesh speck = test::quad_grid(2, 2);
  Topology all = sheet.topology;
  std::vector<float> xyz = sheet.positions;
  for (uint32_t k = 0; k < 4; ++k) {
    const uint32_t first = all.vertex_count;
    all.vertex_count += speck.topology.vertex_count;
    for (Face f : speck.topology.faces) {
      for (uint32_t& c : f.v)
        if (c != kNoVertex) c += first;
      all.add_face(f, 0);
    }
    for (size_t i = 0; i < speck.positions.size(); ++i)
      xyz.push_back(speck.positions[i] + (i % 3 == 2 ? 20.0f + k : 0.0f));
  }
  all.node_ids.resize(all.vertex_count);
  Frames frames;
  frames.set_vertex_count(all.vertex_count);
  frames.add_step(xyz, 0);
  SimplifyOptions to_target;
  to_target.target_ratio = 0.5;
  auto r = simplify(all, frames, to_target);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->regions, size_t{1} << simplification::kRegionLevels);
  EXPECT_TRUE(island_vertex_counts(all, to_target).empty());
  SimplifyOptions to_the_end;
  r = simplify(all, frames, to_the_end);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->regions, 0u);
  EXPECT_GE(r->islands, 2u);
  EXPECT_EQ(island_vertex_counts(all, to_the_end).size(), r->islands);
}

}  // namespace
}  // namespace dynpm
