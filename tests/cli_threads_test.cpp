// `dynpm build --threads N`: the .dpm is the same byte for byte on one thread and on two, on real
// CalculiX results (the crash box's .frd, read several steps at once, its OBJ sequence, and a
// family of it and a second run of its mesh).
#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

test::CommandResult dynpm_cli(const std::string& arguments) {
  return test::run_command(std::string(DYNPM_CLI) + " " + arguments);
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// Builds `input` with --threads 1 and 2 under each key-step rule; both files must be equal.
void expect_same_on_any_thread_count(const test::TempDir& dir, const std::string& input) {
  for (const char* rule : {"auto:3", "all"}) {
    std::string files[2];
    for (int threads = 1; threads <= 2; ++threads) {
      files[threads - 1] = dir.file("t" + std::to_string(threads) + ".dpm");
      auto r = dynpm_cli("build " + input + " -o " + files[threads - 1] + " --key-steps " + rule +
                         " --threads " + std::to_string(threads));
      ASSERT_EQ(r.exit_code, 0) << r.output;
    }
    const std::string one = slurp(files[0]);
    EXPECT_GT(one.size(), 1000u);
    EXPECT_TRUE(one == slurp(files[1])) << input << " --key-steps " << rule;
    EXPECT_EQ(std::system(("cmp -s " + files[0] + " " + files[1]).c_str()), 0);
  }
}

TEST(CliThreads, TheCrashBoxFrdBuildsTheSameOnOneAndTwoThreads) {
  test::TempDir dir;
  const std::string gz = test::shared_data() + "/crashbox-s/crashbox-s.frd.gz";
  const std::string frd = dir.file("crashbox-s.frd");
  if (std::system(("zcat '" + gz + "' > '" + frd + "' 2>/dev/null").c_str()) != 0)
    GTEST_SKIP() << "../shared/data/crashbox-s is missing";
  expect_same_on_any_thread_count(dir, frd);
}

TEST(CliThreads, TheCrashBoxObjSequenceBuildsTheSameOnOneAndTwoThreads) {
  test::TempDir dir;
  const std::string folder = test::shared_data() + "/crashbox-mixed-5k/obj";
  if (!std::filesystem::exists(folder)) GTEST_SKIP() << folder << " is missing";
  expect_same_on_any_thread_count(dir, "'" + folder + "/frame_*.obj'");
}

// A family's steps are read and hashed several at a time, then compared in order.
TEST(CliThreads, ACrashBoxFamilyBuildsTheSameOnOneAndTwoThreads) {
  test::TempDir dir;
  const std::string crush = dir.file("crashbox-s.frd"), bent = dir.file("crashbox-bent.frd");
  if (std::system(("zcat '" + test::shared_data() + "/crashbox-s/crashbox-s.frd.gz' > '" + crush +
                   "' 2>/dev/null")
                      .c_str()) != 0)
    GTEST_SKIP() << "../shared/data/crashbox-s is missing";
  ASSERT_EQ(std::system(("zcat '" + test::source_dir() + "/bench/family/crashbox-bent.frd.gz' > '" +
                         bent + "'")
                            .c_str()),
            0);
  expect_same_on_any_thread_count(dir, "--family '" + crush + "' '" + bent + "'");
}

TEST(CliThreads, ABadThreadCountIsAUsageError) {
  auto r = dynpm_cli("build x.obj -o x.dpm --threads many");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--threads"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace dynpm
