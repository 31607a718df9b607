// Key steps (paper §3): which steps rate collapses, and that every key step's geometry counts.
#include <gtest/gtest.h>

#include <cmath>

#include "core/face_geometry.h"
#include "dynpm/io.h"
#include "dynpm/simplify.h"
#include "fixtures.h"

namespace dynpm {
namespace {

TEST(KeySteps, ParseRules) {
  EXPECT_EQ(parse_key_step_rule("all")->kind, KeyStepRule::Kind::kAll);
  EXPECT_EQ(parse_key_step_rule("paper")->kind, KeyStepRule::Kind::kPaper);
  auto a = parse_key_step_rule("auto:4");
  ASSERT_TRUE(a.ok());
  EXPECT_EQ(a->kind, KeyStepRule::Kind::kAuto);
  EXPECT_EQ(a->count, 4u);
  auto list = parse_key_step_rule("0,12,24");
  ASSERT_TRUE(list.ok());
  EXPECT_EQ(list->steps, (std::vector<size_t>{0, 12, 24}));
  for (const char* bad : {"", "auto:", "auto:0", "1,,2", "x", "3,", "-1"})
    EXPECT_FALSE(parse_key_step_rule(bad).ok()) << bad;
}

// A grid whose vertex 0 moves by d[t] along z in step t.
Frames moving_corner(const test::Mesh& m, std::vector<float> d) {
  Frames frames(m.topology.vertex_count);
  for (size_t t = 0; t < d.size(); ++t) {
    std::vector<float> xyz = m.positions;
    xyz[2] = d[t];
    frames.add_step(xyz, double(t));
  }
  return frames;
}

TEST(KeySteps, PaperTakesFirstLastAndTheStrongestInBetween) {
  const auto m = test::quad_grid(3, 3);
  const Frames frames = moving_corner(m, {0, 1, 5, 2, 1});
  auto choice = choose_key_steps(frames, *parse_key_step_rule("paper"));
  ASSERT_TRUE(choice.ok());
  EXPECT_EQ(choice->steps, (std::vector<size_t>{0, 2, 4}));
  EXPECT_EQ(choice->reasons.size(), 3u);
  EXPECT_NE(choice->reasons[1].find("strongest"), std::string::npos);
}

TEST(KeySteps, AutoAddsTheFarthestStepEachTime) {
  const auto m = test::quad_grid(3, 3);
  const Frames frames = moving_corner(m, {0, 1, 5, 2, 9, 8});
  auto choice = choose_key_steps(frames, *parse_key_step_rule("auto:3"));
  ASSERT_TRUE(choice.ok());
  // From step 0 the farthest is step 4 (9 away); then the step whose nearer chosen step is
  // farthest: step 2 (5 from step 0, 4 from step 4).
  EXPECT_EQ(choice->steps, (std::vector<size_t>{0, 2, 4}));
  auto all = choose_key_steps(frames, *parse_key_step_rule("auto:10"));
  ASSERT_TRUE(all.ok());
  EXPECT_EQ(all->steps.size(), 6u);  // never more than the steps there are
}

TEST(KeySteps, ExplicitStepsMustExist) {
  const auto m = test::quad_grid(2, 2);
  const Frames frames = moving_corner(m, {0, 1, 2});
  EXPECT_TRUE(choose_key_steps(frames, *parse_key_step_rule("2,0")).ok());
  auto bad = choose_key_steps(frames, *parse_key_step_rule("0,3"));
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("key step 3 does not exist"), std::string::npos);
}

TEST(KeySteps, TheCrashBoxPicksSpreadSteps) {
  const std::string folder = test::shared_data() + "/crashbox-s/obj";
  if (!std::filesystem::exists(folder)) GTEST_SKIP() << "../shared/data is not beside the project";
  auto paths = expand_inputs(std::vector<std::string>{folder + "/frame_*.obj"});
  auto stream = open_animation(*paths);
  ASSERT_TRUE(stream.ok());
  auto choice = choose_key_steps(*stream->frames, *parse_key_step_rule("auto:3"));
  ASSERT_TRUE(choice.ok()) << choice.message();
  ASSERT_EQ(choice->steps.size(), 3u);
  EXPECT_EQ(choice->steps.front(), 0u);
  EXPECT_EQ(choice->steps.back(), 25u);  // the crush grows to the end
  EXPECT_GT(choice->steps[1], 5u);
  EXPECT_LT(choice->steps[1], 20u);
}

// The z component of every face normal of a height-field mesh, in one step.
double lowest_normal_z(const Topology& t, std::span<const float> xyz) {
  double lowest = 1;
  for (const Face& f : t.faces) {
    const int d = f.degree();
    Vec3 p[4];
    for (int i = 0; i < d; ++i) p[i] = load(&xyz[size_t{f.v[i]} * 3]);
    const Vec3 n = doubled_vector_area(p, d);
    lowest = std::min(lowest, n.z / length(n));
  }
  return lowest;
}

TEST(KeySteps, NoFaceFoldsOverInAnyKeyStep) {
  // Step 0 is flat; step 1 is a steep ridge field, waved a little along the ridges too (ridges
  // straight along y would let the simplifier reach 60 vertices at no cost: the error check at
  // the end would then compare rounding noise with 0). Rated on every step, no face of the
  // result turns over in either step (the grid is a height field, so every normal points up).
  auto m = test::quad_grid(16, 16);
  Frames frames(m.topology.vertex_count);
  frames.add_step(m.positions, 0);
  std::vector<float> ridges = m.positions;
  for (size_t v = 0; v < ridges.size(); v += 3)
    ridges[v + 2] = 1.5f * std::sin(ridges[v] * 1.3f) + 0.3f * std::sin(ridges[v + 1] * 0.7f);
  frames.add_step(ridges, 1);
  ASSERT_GT(lowest_normal_z(m.topology, ridges), 0);

  SimplifyOptions options;
  options.target_vertices = 60;
  options.check_every_collapse = true;
  auto r = simplify(m.topology, frames, options);
  ASSERT_TRUE(r.ok()) << r.message();
  for (size_t t = 0; t < 2; ++t) {
    std::vector<float> xyz;
    for (uint32_t v : r->original_vertex)
      xyz.insert(xyz.end(), &frames.step(t)[v * 3], &frames.step(t)[v * 3] + 3);
    EXPECT_GT(lowest_normal_z(r->topology, xyz), 0) << "step " << t;
  }

  // Rated on the flat step alone, the ridges are invisible to the simplifier: it stays valid
  // but its error in step 1 is what the key steps are for.
  options.key_steps = {0};
  auto flat = simplify(m.topology, frames, options);
  ASSERT_TRUE(flat.ok());
  EXPECT_EQ(flat->max_error, 0.0);
  EXPECT_GT(r->max_error, 0.0);
}

}  // namespace
}  // namespace dynpm
