// Property tests on seeded random mixed meshes (random_meshes.h), 2 of 3: each mesh goes through
// build → .dpm → full refinement: the input comes back, face for face, with its ids and positions
// (bit-exact lossless, else within the stated bound).
// A failure names its seed (SCOPED_TRACE) and the mesh it made (random_meshes.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <string_view>

#include "random_meshes.h"
#include "round_trip.h"

namespace dynpm {
namespace {

using namespace test;

// ---------------------------------------------------------------------------------------------
// 2. build → .dpm → full refinement gives the input back

void expect_same_record(const ProgressiveMesh& a, const ProgressiveMesh& b) {
  EXPECT_EQ(a.base_vertex_count, b.base_vertex_count);
  EXPECT_EQ(a.base_faces, b.base_faces);
  EXPECT_EQ(a.base_error, b.base_error);
  EXPECT_EQ(a.max_error, b.max_error);
  expect_same_split_records(a, b);
  EXPECT_EQ(a.key_steps, b.key_steps);
  EXPECT_EQ(a.times, b.times);
  EXPECT_TRUE(a.positions == b.positions) << "positions differ";
}

TEST(PropertyProgressive, BuildThenFullRefinementGivesTheInputBack) {
  for (uint32_t seed : seeds(2000, 12)) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Rng rng(seed);
    const RandomCase c = random_case(rng, 6000);
    SCOPED_TRACE(c.description);
    const Animation& a = c.animation;
    const BuildOptions o = random_build_options(rng, a);
    SCOPED_TRACE(describe(o.simplify) + (o.lossless ? ", lossless" : ", bound ") +
                 (o.lossless ? "" : std::to_string(o.max_position_error)));
    auto built = build_progressive_mesh(a.topology, a.frames, o);
    ASSERT_TRUE(built.ok()) << built.message();
    test::expect_input_back(a, *built, o.max_position_error);
    const std::string bytes = encode_dpm(*built).value();
    auto decoded = decode_dpm(bytes, "memory.dpm");
    ASSERT_TRUE(decoded.ok()) << decoded.message();
    test::expect_input_back(a, *decoded, o.max_position_error);
    expect_same_record(*built, *decoded);

    // A prefix of the file decodes to a coarser mesh of the same record, or to an error.
    for (int cut = 0; cut < 3; ++cut) {
      const size_t size = pick(rng, 0, uint32_t(bytes.size() - 1));
      auto prefix = decode_dpm(std::string_view(bytes).substr(0, size), "prefix.dpm");
      if (!prefix.ok()) continue;
      SCOPED_TRACE("prefix of " + std::to_string(size) + " bytes");
      EXPECT_FALSE(prefix->complete);
      ASSERT_LE(prefix->split_count(), built->split_count());
      Navigator part(*prefix), whole(*decoded);
      part.set_level(prefix->split_count());
      whole.set_level(prefix->split_count());
      expect_clean(part.topology(), "prefix");
      EXPECT_TRUE(std::ranges::equal(part.faces(), whole.faces()));
    }
  }
}

}  // namespace
}  // namespace dynpm
