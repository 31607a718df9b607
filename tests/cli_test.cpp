// The dynpm command as a user runs it: exit codes, messages, and files.
#include <gtest/gtest.h>

#include <fstream>

#include "dynpm/io.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

test::CommandResult dynpm_cli(const std::string& arguments) {
  return test::run_command(std::string(DYNPM_CLI) + " " + arguments);
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::string crashbox_glob() { return test::shared_data() + "/crashbox-s/obj/frame_*.obj"; }

TEST(Cli, InfoOnTheCalculixCrashBox) {
  if (!std::filesystem::exists(test::shared_data())) GTEST_SKIP() << "no ../shared/data";
  auto r = dynpm_cli("info '" + crashbox_glob() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "vertices      3003")) << r.output;
  EXPECT_TRUE(contains(r.output, "2937 faces") ||
              contains(r.output, "2937 (2937 quads, 0 triangles)"))
      << r.output;
  EXPECT_TRUE(contains(r.output, "time steps    26")) << r.output;
  EXPECT_TRUE(contains(r.output, "validation    ok")) << r.output;

  auto json = dynpm_cli("info --json '" + crashbox_glob() + "'");
  ASSERT_EQ(json.exit_code, 0) << json.output;
  for (const char* field : {"\"vertices\": 3003", "\"quads\": 2937", "\"triangles\": 0",
                            "\"steps\": 26", "\"ok\": true"})
    EXPECT_TRUE(contains(json.output, field)) << field << "\n" << json.output;
}

TEST(Cli, InfoReportsValidationErrorsWithExitCode3) {
  test::TempDir dir;
  const auto m = test::valence_two_quads();
  ASSERT_TRUE(write_mesh(dir.file("m2.obj"), m.topology, m.positions).ok());
  auto r = dynpm_cli("info " + dir.file("m2.obj"));
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_TRUE(contains(r.output, "INVALID")) << r.output;
  EXPECT_TRUE(contains(r.output, "(M2)")) << r.output;
}

TEST(Cli, BadInputIsAClearErrorAndNonZeroExit) {
  test::TempDir dir;
  std::ofstream(dir.file("bad.obj")) << "v 0 0 0\nv 1 0 0\nf 1 2 7\n";
  auto r = dynpm_cli("info " + dir.file("bad.obj"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.output, dir.file("bad.obj") + ":3: face index 7")) << r.output;

  auto missing = dynpm_cli("info " + dir.file("missing.obj"));
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_TRUE(contains(missing.output, "no such file")) << missing.output;

  auto usage = dynpm_cli("info --bogus x.obj");
  EXPECT_EQ(usage.exit_code, 2);
  EXPECT_TRUE(contains(usage.output, "unknown option '--bogus'")) << usage.output;
}

TEST(Cli, EveryVerbHasHelp) {
  for (const char* verb : {"info", "convert"}) {
    auto r = dynpm_cli(std::string(verb) + " --help");
    EXPECT_EQ(r.exit_code, 0) << verb;
    EXPECT_TRUE(contains(r.output, std::string("usage: dynpm ") + verb)) << r.output;
  }
  auto top = dynpm_cli("--help");
  EXPECT_EQ(top.exit_code, 0);
  EXPECT_TRUE(contains(top.output, "convert"));
}

TEST(Cli, ConvertAnAnimationToPlyAndBackKeepsEverything) {
  if (!std::filesystem::exists(test::shared_data())) GTEST_SKIP() << "no ../shared/data";
  test::TempDir dir;
  auto r = dynpm_cli("convert '" + crashbox_glob() + "' -o " + dir.file("step_{:02d}.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "wrote 26 steps")) << r.output;
  auto original = read_animation(*expand_inputs(std::vector<std::string>{crashbox_glob()}));
  auto converted = read_animation(*expand_inputs(std::vector<std::string>{dir.file("step_*.ply")}));
  ASSERT_TRUE(original.ok() && converted.ok()) << converted.message();
  EXPECT_EQ(converted->topology.faces, original->topology.faces);
  ASSERT_EQ(converted->step_count(), 26u);
  for (size_t t = 0; t < 26; ++t) {
    auto a = original->frames.step(t), b = converted->frames.step(t);
    EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << "step " << t;
    EXPECT_DOUBLE_EQ(converted->frames.step_time(t), original->frames.step_time(t));
  }
}

TEST(Cli, ConvertNeedsAStepPatternForSeveralSteps) {
  if (!std::filesystem::exists(test::shared_data())) GTEST_SKIP() << "no ../shared/data";
  test::TempDir dir;
  auto r = dynpm_cli("convert '" + crashbox_glob() + "' -o " + dir.file("one.ply"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.output, "26 time steps")) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("one.ply")));
}

}  // namespace
}  // namespace dynpm
