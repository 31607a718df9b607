// Islands (docs/simplify.md "Islands"): a mesh of several connected components, simplified to the
// end, runs each island's queue on its own on any free thread. The collapses and the result must
// not depend on the thread count, every round must leave a valid mesh, the collapses are told in
// key order, and a progressive mesh built that way gives the input back exactly.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <map>
#include <vector>

#include "crash_box.h"
#include "dynpm/io.h"
#include "dynpm/pipeline.h"
#include "dynpm/simplify.h"
#include "fixtures.h"
#include "round_trip.h"
#include "simplify/islands.h"

namespace dynpm {
namespace {

// `copies` crash boxes side by side, each its own part and component, and a lone quad. With
// `interleaved`, copy k's vertex v is numbered v · copies + k, so that no island is one run of
// numbers. Copy k is `growth`^k times the box's size.
Animation tiled(const Animation& box, uint32_t copies, bool interleaved, float growth = 1) {
  const uint32_t n = box.topology.vertex_count;
  auto id = [&](uint32_t k, uint32_t v) { return interleaved ? v * copies + k : k * n + v; };
  Animation a;
  a.topology = Topology::with_vertices(n * copies + 4);
  for (uint32_t k = 0; k < copies; ++k)
    for (const Face& f : box.topology.faces) {
      Face g = f;
      for (uint32_t& c : g.v)
        if (c != kNoVertex) c = id(k, c);
      a.topology.add_face(g, static_cast<int32_t>(k + 1));
    }
  const uint32_t q = n * copies;
  a.topology.add_quad(q, q + 1, q + 2, q + 3, static_cast<int32_t>(copies + 1));
  a.frames.set_vertex_count(a.topology.vertex_count);
  for (size_t t = 0; t < box.step_count(); ++t) {
    const auto step = box.frames.step(t);
    std::vector<float> xyz(size_t{a.topology.vertex_count} * 3);
    for (uint32_t k = 0; k < copies; ++k)
      for (uint32_t v = 0; v < n; ++v)
        for (int c = 0; c < 3; ++c)
          xyz[size_t{id(k, v)} * 3 + c] = step[size_t{v} * 3 + c] * std::pow(growth, float(k)) +
                                          (c == 0 ? 400.0f * k * std::pow(growth, float(k)) : 0.0f);
    const float quad[12] = {-100, 0, 0, -90, 0, 0, -90, 10, float(t), -100, 10, 0};
    std::copy(quad, quad + 12, xyz.begin() + size_t{q} * 3);
    a.frames.add_step(std::move(xyz), box.frames.step_time(t));
  }
  return a;
}

using test::crashbox;
using test::Told;

SimplifyOptions island_options(unsigned threads) {
  SimplifyOptions o;
  o.key_steps = {0, 12, 25};
  o.island_min_vertices = 0;  // islands on a small mesh too
  o.threads = threads;
  return o;
}

TEST(Islands, TheSameCollapsesAndMeshOnAnyThreadCount) {
  const Animation* box = crashbox();
  ASSERT_NE(box, nullptr);
  for (bool interleaved : {false, true}) {
    SCOPED_TRACE(interleaved ? "interleaved numbers" : "copies in runs");
    const Animation a = tiled(*box, 3, interleaved);
    Told first;
    auto reference = simplify(a.topology, a.frames, island_options(1), &first);
    ASSERT_TRUE(reference.ok()) << reference.message();
    EXPECT_EQ(reference->islands, 4u);  // three boxes and the quad, each a 64th or more
    EXPECT_EQ(reference->collapses, first.collapses.size());
    EXPECT_GT(reference->collapses, 2u * 2900);
    for (unsigned threads : {2u, 3u, 8u}) {
      Told told;
      auto r = simplify(a.topology, a.frames, island_options(threads), &told);
      ASSERT_TRUE(r.ok()) << r.message();
      EXPECT_TRUE(told.collapses == first.collapses) << threads << " threads";
      EXPECT_EQ(r->topology.faces, reference->topology.faces) << threads << " threads";
      EXPECT_EQ(r->original_vertex, reference->original_vertex) << threads << " threads";
    }
  }
}

// Islands that run to their ends on two threads tell the collapses done so far as they go, one
// report at a time: never falling, never past the goal, ending at the collapse count.
TEST(Islands, ProgressIsToldAsTheIslandsGo) {
  const Animation* box = crashbox();
  ASSERT_NE(box, nullptr);
  const Animation a = tiled(*box, 6, false);
  SimplifyOptions o = island_options(2);
  std::vector<std::pair<size_t, size_t>> told;  // done, total
  std::atomic<int> inside{0};
  bool overlapped = false;
  o.progress = [&](std::string_view phase, size_t done, size_t total) {
    if (phase != "collapsing") return;
    overlapped |= ++inside > 1;
    told.emplace_back(done, total);
    --inside;
  };
  auto r = simplify(a.topology, a.frames, o);
  ASSERT_TRUE(r.ok()) << r.message();
  ASSERT_EQ(r->islands, 7u);
  EXPECT_FALSE(overlapped);
  ASSERT_GE(told.size(), 2u + 7u);  // the start, each island, the end
  for (size_t k = 1; k < told.size(); ++k) {
    EXPECT_GE(told[k].first, told[k - 1].first) << k;
    EXPECT_LE(told[k].first, told[k].second) << k;
  }
  EXPECT_EQ(told.front().first, 0u);
  EXPECT_EQ(told.back().first, r->collapses);
  EXPECT_EQ(told[told.size() - 2].first, r->collapses);  // the last island's report: all of them
}

// An island's log grows in chunks of 64 KB, 128 KB, … 2 MB and is read once from the front,
// each chunk given back as the reading passes it: every item reads back as written, across the
// growing chunks and the 2 MB ones after them, with the chunks behind the reading released.
TEST(Islands, ALogReadsBackWhatWasWrittenAcrossItsChunks) {
  simplification::ChunkedArray<uint32_t> log;
  const uint32_t n = 1'500'000;  // 64 KB holds 16,384: five growing chunks, then 2 MB ones
  for (uint32_t i = 0; i < n; ++i) log.push_back(i * 2654435761u);
  ASSERT_EQ(log.size(), n);
  for (uint32_t i = 0; i < n; ++i) {
    ASSERT_EQ(log[i], i * 2654435761u) << i;
    log.release_before(i);
  }
}

// Only the islands at work hold key-step quadrics (with every key step, most of the memory): at
// most 2 × threads of them at once (threads when no round is needed), each given back when it is
// done; the collapses are the same.
TEST(Islands, OnlyTheIslandsAtWorkHoldQuadrics) {
  const Animation* box = crashbox();
  ASSERT_NE(box, nullptr);
  const Animation a = tiled(*box, 6, false);
  const uint32_t n = box->topology.vertex_count;
  Told one_thread, many;
  auto r = simplify(a.topology, a.frames, island_options(1), &one_thread);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->islands, 7u);               // six boxes and the quad
  EXPECT_EQ(r->quadric_vertices_held, n);  // one thread, no rounds: one island at a time
  // What a memory estimate is told before the work: the two largest islands.
  EXPECT_EQ(quadric_vertices_held(a.topology, island_options(1)), 2 * n);
  EXPECT_EQ(quadric_vertices_held(a.topology, island_options(8)), a.topology.vertex_count);
  auto all_open = simplify(a.topology, a.frames, island_options(8), &many);
  ASSERT_TRUE(all_open.ok()) << all_open.message();
  // Up to 8 at once (≥ 7 islands), as the threads happen to overlap.
  EXPECT_GE(all_open->quadric_vertices_held, n);
  EXPECT_LE(all_open->quadric_vertices_held, a.topology.vertex_count);
  EXPECT_TRUE(many.collapses == one_thread.collapses);
  // Fewer at once than the threads would take (what `dynpm build` chooses when memory is short):
  // the same collapses, one island's quadrics at a time.
  SimplifyOptions one_at_a_time = island_options(8);
  one_at_a_time.islands_at_once = 1;
  Told alone;
  auto single = simplify(a.topology, a.frames, one_at_a_time, &alone);
  ASSERT_TRUE(single.ok()) << single.message();
  EXPECT_EQ(single->quadric_vertices_held, n);
  EXPECT_EQ(quadric_vertices_held(a.topology, one_at_a_time), n);
  EXPECT_TRUE(alone.collapses == one_thread.collapses);
  SimplifyOptions whole = island_options(1);
  whole.island_min_vertices = UINT32_MAX;
  auto serial = simplify(a.topology, a.frames, whole);
  ASSERT_TRUE(serial.ok()) << serial.message();
  EXPECT_EQ(serial->quadric_vertices_held, a.topology.vertex_count);
  EXPECT_EQ(quadric_vertices_held(a.topology, whole), a.topology.vertex_count);
}

TEST(Islands, EveryRoundLeavesAValidMeshAndKeysNeverFall) {
  const Animation* box = crashbox();
  ASSERT_NE(box, nullptr);
  const Animation a = tiled(*box, 3, true);
  SimplifyOptions o = island_options(2);
  o.check_every_collapse = true;  // with islands: the whole mesh after every round
  Told told;
  auto r = simplify(a.topology, a.frames, o, &told);
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_EQ(r->islands, 4u);
  EXPECT_FALSE(r->target_reached);  // run to the end: no legal collapse remains
  // Each island's key is the largest error (as a float) of its collapses so far; told in key
  // order, those keys never fall. An island here is a box (vertex v of box v mod 3) or the quad.
  const uint32_t boxes = 3 * box->topology.vertex_count;
  std::map<uint32_t, float> key;
  float told_key = 0;
  for (const Told::Collapse& c : told.collapses) {
    const uint32_t island = c.v0 < boxes ? c.v0 % 3 : 3;
    EXPECT_EQ(c.v1 < boxes ? c.v1 % 3 : 3, island);
    float& k = key[island];
    k = std::max(k, static_cast<float>(c.error));
    EXPECT_GE(k, told_key);
    told_key = k;
  }
  EXPECT_EQ(key.size(), 4u);  // the lone quad collapsed too (into a triangle)
  // The serial loop on the same mesh reaches a base of the same size within a few vertices.
  SimplifyOptions serial = o;
  serial.island_min_vertices = UINT32_MAX;
  serial.check_every_collapse = false;
  auto whole = simplify(a.topology, a.frames, serial);
  ASSERT_TRUE(whole.ok()) << whole.message();
  EXPECT_EQ(whole->islands, 1u);
  EXPECT_NEAR(double(r->topology.vertex_count), double(whole->topology.vertex_count),
              0.05 * whole->topology.vertex_count);
}

// With a stop condition the islands still run to their ends; the cut is made in key order and
// the result is the input with the told collapses replayed: exact targets, a valid mesh, the
// same on any thread count, and every told collapse within the maximum error.
TEST(Islands, AStopConditionCutsTheCollapsesInKeyOrder) {
  const Animation* box = crashbox();
  ASSERT_NE(box, nullptr);
  const Animation a = tiled(*box, 3, true);
  const uint32_t referenced = 3 * box->topology.vertex_count + 4;
  for (int stop = 0; stop < 3; ++stop) {
    SCOPED_TRACE(stop);
    Topology first_mesh;
    Told first;
    for (unsigned threads : {1u, 2u, 3u}) {
      SimplifyOptions o = island_options(threads);
      o.check_every_collapse = true;  // every round and the mesh at the cut
      if (stop == 0) o.target_ratio = 0.1;
      if (stop == 1) o.target_faces = 1500;
      if (stop == 2) o.max_error = 0.002;
      Told told;
      auto r = simplify(a.topology, a.frames, o, &told);
      ASSERT_TRUE(r.ok()) << r.message();
      EXPECT_EQ(r->islands, 4u);
      EXPECT_TRUE(r->target_reached) << r->stop_reason;
      EXPECT_EQ(r->collapses, told.collapses.size());
      EXPECT_EQ(r->topology.vertex_count, referenced - told.collapses.size());
      if (stop == 0) {
        EXPECT_EQ(r->topology.vertex_count, uint32_t(std::ceil(0.1 * referenced)));
      }
      if (stop == 1) {
        EXPECT_EQ(r->topology.faces.size(), 1500u);
      }
      if (stop == 2) {
        EXPECT_NE(r->stop_reason.find("maximum error"), std::string::npos) << r->stop_reason;
        for (const Told::Collapse& c : told.collapses)
          EXPECT_LE(static_cast<float>(c.error), 0.002f);
      }
      if (threads == 1) {
        first_mesh = r->topology, first = told;
        continue;
      }
      EXPECT_EQ(r->topology.faces, first_mesh.faces) << threads << " threads";
      EXPECT_TRUE(told.collapses == first.collapses) << threads << " threads";
    }
  }
}

// With a vertex or face target an island stops once its key is past a bound of the cut: the
// told collapses are exactly the first ones the islands tell when run to their ends, and fewer
// collapses are made than that run made. The boxes differ in size (1, 3 and 9 times), so that
// their keys grow at different rates and some islands are still short of the cut when others
// are past it.
TEST(Islands, IslandsStopPastTheCutAndTellTheSameCollapses) {
  const Animation* box = crashbox();
  ASSERT_NE(box, nullptr);
  const Animation a = tiled(*box, 3, true, 3.0f);
  Told all;
  auto to_the_end = simplify(a.topology, a.frames, island_options(2), &all);
  ASSERT_TRUE(to_the_end.ok()) << to_the_end.message();
  ASSERT_EQ(to_the_end->collapses_made, all.collapses.size());
  for (int stop = 0; stop < 9; ++stop) {
    SCOPED_TRACE(stop);
    SimplifyOptions o = island_options(2);
    if (stop < 6) o.target_ratio = 0.9 - 0.15 * stop;  // 90 % down to 15 %
    if (stop >= 6) o.target_faces = 2000 * (stop - 4);
    Told told;
    auto r = simplify(a.topology, a.frames, o, &told);
    ASSERT_TRUE(r.ok()) << r.message();
    EXPECT_TRUE(r->target_reached) << r->stop_reason;
    ASSERT_LE(told.collapses.size(), all.collapses.size());
    EXPECT_TRUE(std::equal(told.collapses.begin(), told.collapses.end(), all.collapses.begin()));
    EXPECT_GE(r->collapses_made, r->collapses);
    // At least a quarter of the collapses past the cut are never made (62–94 % here).
    const size_t past = all.collapses.size() - told.collapses.size();
    EXPECT_GE(all.collapses.size() - r->collapses_made, past / 4)
        << "the islands ran on past the cut: " << r->collapses_made << " of "
        << all.collapses.size() << " made, " << told.collapses.size() << " told";
  }
}

TEST(Islands, AProgressiveMeshBuiltOnIslandsGivesTheInputBack) {
  const Animation* box = crashbox();
  ASSERT_NE(box, nullptr);
  const Animation a = tiled(*box, 3, true);
  BuildOptions options;
  options.simplify.key_steps = {0, 12, 25};
  options.simplify.island_min_vertices = 0;
  options.lossless = true;
  std::string first;
  for (unsigned threads : {1u, 2u}) {
    options.simplify.threads = threads;
    auto pm = build_progressive_mesh(a.topology, a.frames, options);
    ASSERT_TRUE(pm.ok()) << pm.message();
    test::expect_input_back(a, test::through_file(*pm));
    const std::string bytes = encode_dpm(*pm, 1).value();
    if (first.empty()) first = bytes;
    EXPECT_TRUE(bytes == first) << threads << " threads";
  }
}

}  // namespace
}  // namespace dynpm
