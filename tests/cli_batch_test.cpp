// 'dynpm batch' on real CalculiX runs (../shared/data, data/hat-rail): what it builds, skips
// and reports, that a killed run's leftovers do not stop the next, that --jobs does not change a
// byte, and 'dynpm catalogue''s index.json against what 'dynpm info' reads from each file.
// The Slurm side runs on a real cluster in tests/slurm_batch.sh.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "dynpm_runs.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

// dynpm with `arguments` in folder `dir` (stdout and stderr together).
test::CommandResult dynpm_in(const fs::path& dir, const std::string& arguments) {
  return test::run_command("cd '" + dir.string() + "' && " + DYNPM_CLI + " " + arguments);
}

// The row of the summary table that starts with `input`, or "".
std::string row_of(const std::string& output, const std::string& input) {
  for (size_t at = 0; at < output.size();) {
    const size_t end = output.find('\n', at);
    const std::string line = output.substr(at, end - at);
    if (line.starts_with(input + " ")) return line;
    if (end == std::string::npos) break;
    at = end + 1;
  }
  return "";
}

// The text of index.json's entry named `name` (up to the next entry).
std::string entry_of(const std::string& index, const std::string& name) {
  const size_t at = index.find("\"name\": \"" + name + "\"");
  if (at == std::string::npos) return "";
  return index.substr(at, index.find("\"built\"", at) - at);
}

// Real inputs in `dir`: the crash box (3,003 nodes) under `names`, each a copy of the file.
void crashbox_copies(const fs::path& dir, std::initializer_list<std::string> names) {
  fs::create_directories(dir);
  const std::string first = (dir / *names.begin()).string();
  ASSERT_EQ(std::system(("zcat '" + test::shared_data() + "/crashbox-s/crashbox-s.frd.gz' > '" +
                         first + "'")
                            .c_str()),
            0);
  for (const std::string& name : names)
    if (dir / name != fs::path(first)) fs::copy_file(first, dir / name);
}

TEST(CliBatch, BuildsThenSkipsWhatIsUpToDateAndRebuildsAChangedInput) {
  test::TempDir tmp;
  crashbox_copies(tmp.path() / "runs", {"a.frd", "b.frd"});
  write(tmp.path() / "runs/list.txt", "# two copies\n\n  a.frd  \nb.frd\n");
  auto first = dynpm_in(tmp.path(), "batch runs/list.txt --out out --key-steps paper -q");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_NE(row_of(first.output, "runs/a.frd").find(" built "), std::string::npos) << first.output;
  EXPECT_NE(row_of(first.output, "runs/b.frd").find(" 3003 "), std::string::npos)
      << first.output;  // the vertices column
  ASSERT_TRUE(fs::exists(tmp.path() / "out/a.dpm") && fs::exists(tmp.path() / "out/b.dpm"));
  const auto a_written = fs::last_write_time(tmp.path() / "out/a.dpm");
  // Every build logged its JSON progress.
  EXPECT_NE(slurp(tmp.path() / "out/logs/a.log").find("{\"phase\":\"writing\""), std::string::npos);

  auto second = dynpm_in(tmp.path(), "batch runs/list.txt --out out --key-steps paper -q");
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_NE(row_of(second.output, "runs/a.frd").find(" skipped "), std::string::npos)
      << second.output;
  EXPECT_EQ(fs::last_write_time(tmp.path() / "out/a.dpm"), a_written);

  // An input changed after its .dpm was written is built again, the other is not.
  fs::last_write_time(tmp.path() / "runs/b.frd",
                      fs::last_write_time(tmp.path() / "out/b.dpm") + std::chrono::seconds(5));
  auto third = dynpm_in(tmp.path(), "batch runs/list.txt --out out --key-steps paper -q");
  ASSERT_EQ(third.exit_code, 0) << third.output;
  EXPECT_NE(row_of(third.output, "runs/a.frd").find(" skipped "), std::string::npos);
  EXPECT_NE(row_of(third.output, "runs/b.frd").find(" built "), std::string::npos) << third.output;
}

TEST(CliBatch, AKilledRunsTemporaryIsRemovedAndItsVariantBuilt) {
  test::TempDir tmp;
  crashbox_copies(tmp.path(), {"a.frd"});
  write(tmp.path() / "list.txt", "a.frd\n");
  // What a build killed while writing leaves: its temporary, no a.dpm; the writer is gone.
  const fs::path stale = tmp.path() / "out/a.dpm.tmp-999999999-0";
  write(stale, "half a file");
  fs::last_write_time(stale, fs::file_time_type::clock::now() - std::chrono::minutes(5));
  auto run = dynpm_in(tmp.path(), "batch list.txt --out out --key-steps paper -q");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(row_of(run.output, "a.frd").find(" built "), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_EQ(test::joined(test::folder_entries(tmp.path() / "out")), "[a.dpm, index.json, logs]");
}

TEST(CliBatch, TwoInputsOfOneNameAreRefusedBeforeAnyWork) {
  test::TempDir tmp;
  crashbox_copies(tmp.path() / "x", {"a.frd"});
  crashbox_copies(tmp.path() / "y", {"a.frd"});
  write(tmp.path() / "list.txt", "x/a.frd\n# the same name\ny/a.frd\n");
  auto run = dynpm_in(tmp.path(), "batch list.txt --out out");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.output.find("list.txt:3: y/a.frd and line 1 (x/a.frd) would both write a.dpm"),
            std::string::npos)
      << run.output;
  EXPECT_FALSE(fs::exists(tmp.path() / "out"));
}

TEST(CliBatch, ABadInputFailsWithItsMessageWhileTheOthersBuild) {
  test::TempDir tmp;
  crashbox_copies(tmp.path(), {"good.frd"});
  fs::copy_file(test::shared_data() + "/crashbox-s/crashbox-s.frd.gz",
                tmp.path() / "packed.frd.gz");
  write(tmp.path() / "list.txt", "packed.frd.gz\ngood.frd\ngone.frd\n");
  auto run = dynpm_in(tmp.path(), "batch list.txt --out out --jobs 2 --key-steps paper -q");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  const std::string packed = row_of(run.output, "packed.frd.gz");
  EXPECT_NE(packed.find(" failed "), std::string::npos) << run.output;
  EXPECT_NE(packed.find("is gzip-compressed; gunzip it first"), std::string::npos) << packed;
  EXPECT_NE(row_of(run.output, "gone.frd").find("no such file"), std::string::npos) << run.output;
  EXPECT_NE(row_of(run.output, "good.frd").find(" built "), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("dynpm batch: failed: packed.frd.gz (line 1), gone.frd (line 3)"),
            std::string::npos)
      << run.output;
  // The catalogue holds what was built, and no half-written file is left.
  EXPECT_EQ(test::joined(test::folder_entries(tmp.path() / "out")), "[good.dpm, index.json, logs]");
  EXPECT_NE(entry_of(slurp(tmp.path() / "out/index.json"), "good"), "");
}

TEST(CliBatch, TwoJobsAtOnceWriteTheSameBytesAsOne) {
  test::TempDir tmp;
  crashbox_copies(tmp.path(), {"a.frd", "b.frd", "c.frd"});
  write(tmp.path() / "list.txt", "*.frd\n");
  auto one = dynpm_in(tmp.path(), "batch list.txt --out one --key-steps paper -q");
  ASSERT_EQ(one.exit_code, 0) << one.output;
  auto two = dynpm_in(tmp.path(), "batch list.txt --out two --jobs 2 --key-steps paper -q");
  ASSERT_EQ(two.exit_code, 0) << two.output;
  for (const char* name : {"a.dpm", "b.dpm", "c.dpm"}) {
    const std::string bytes = slurp(tmp.path() / "one" / name);
    EXPECT_GT(bytes.size(), 1000u) << name;
    EXPECT_EQ(bytes, slurp(tmp.path() / "two" / name)) << name;
  }
}

TEST(CliBatch, SlurmDryRunPrintsQuotedScriptsAndWritesNothing) {
  test::TempDir tmp;
  crashbox_copies(tmp.path() / "plain", {"a.frd", "b.frd"});
  fs::rename(tmp.path() / "plain", tmp.path() / "it's here");
  write(tmp.path() / "it's here/list.txt", "a.frd\nb.frd\n");
  auto run = dynpm_in(tmp.path(),
                      "batch \"it's here/list.txt\" --out out --slurm --dry-run "
                      "--max-running 1 --time 00:10:00 --mem 2G --field-weight 0");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string out = fs::absolute(tmp.path() / "out").string();
  EXPECT_NE(run.output.find((tmp.path() / "it's here/b.frd").string() + "\n"), std::string::npos)
      << run.output;  // the frozen list the tasks read
  EXPECT_NE(run.output.find("'--out' '" + out +
                            "' '--field-weight=0' --task "
                            "\"$SLURM_ARRAY_TASK_ID\""),
            std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("'sbatch' '--parsable' '--job-name=dynpm-build' '--array=0-1%1'"),
            std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("'--time=00:10:00' '--mem=2G'"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("'--dependency=afterok:ARRAY_JOB_ID'"), std::string::npos)
      << run.output;
  EXPECT_FALSE(fs::exists(tmp.path() / "out"));
  // A flag a build would refuse is refused once, before anything is submitted.
  auto bad = dynpm_in(tmp.path(),
                      "batch \"it's here/list.txt\" --out out --slurm --dry-run "
                      "--position-error 2");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
}

// index.json against 'dynpm info --json' of each file: the hat-rail (three node fields) and the
// crash box (none), in a folder and a subfolder.
TEST(CliCatalogue, IndexHoldsWhatEachFileHolds) {
  test::TempDir tmp;
  crashbox_copies(tmp.path() / "set", {"box.frd"});
  ASSERT_EQ(std::system(("zcat '" + test::source_dir() + "/data/hat-rail/rail.frd.gz' > '" +
                         (tmp.path() / "rail.frd").string() + "'")
                            .c_str()),
            0);
  write(tmp.path() / "list.txt", "rail.frd\n");
  fs::create_directories(tmp.path() / "dpm/sub");
  ASSERT_EQ(dynpm_in(tmp.path(), "batch list.txt --out dpm --key-steps paper -q").exit_code, 0);
  ASSERT_EQ(
      dynpm_in(tmp.path(), "build set/box.frd -o dpm/sub/box.dpm --key-steps paper -q").exit_code,
      0);
  write(tmp.path() / "dpm/broken.dpm", "not a dpm");
  auto run = dynpm_in(tmp.path(), "catalogue dpm");
  EXPECT_EQ(run.exit_code, 1) << run.output;  // broken.dpm cannot be read
  EXPECT_NE(run.output.find("wrote dpm/index.json: 2 files"), std::string::npos) << run.output;
  const std::string index = slurp(tmp.path() / "dpm/index.json");
  EXPECT_NE(index.find("\"format\": \"dynpm-catalogue\""), std::string::npos);
  EXPECT_NE(index.find("dpm/broken.dpm"), std::string::npos) << index;  // under "problems"

  const std::string rail = entry_of(index, "rail"), box = entry_of(index, "box");
  ASSERT_NE(rail, "") << index;
  ASSERT_NE(box, "") << index;
  const auto info = [&](const std::string& file) {
    return dynpm_in(tmp.path(), "info dpm/" + file + " --json").output;
  };
  const std::string rail_info = info("rail.dpm"), box_info = info("sub/box.dpm");
  for (const char* key : {"\"vertices\": ", "\"faces\": ", "\"steps\": ", "\"bytes\": "}) {
    const auto value = [&](const std::string& text) {
      const size_t at = text.find(key);
      return at == std::string::npos ? std::string("?")
                                     : text.substr(at, text.find_first_of(",\n", at) - at);
    };
    EXPECT_EQ(value(rail), value(rail_info)) << key;
    EXPECT_EQ(value(box), value(box_info)) << key;
  }
  EXPECT_NE(rail.find("\"vertices\": 2608"), std::string::npos) << rail;
  EXPECT_NE(rail.find("\"path\": \"rail.dpm\""), std::string::npos) << rail;
  EXPECT_NE(rail.find("\"source\": \"rail.frd\""), std::string::npos) << rail;
  for (const char* field : {"S_MISES", "PEEQ", "ERROR"})
    EXPECT_NE(rail.find("\"name\": \"" + std::string(field) +
                        "\",\n          \"location\": "
                        "\"node\""),
              std::string::npos)
        << field << rail;
  EXPECT_NE(rail.find("\"last_time\": 30"), std::string::npos) << rail;
  EXPECT_NE(box.find("\"path\": \"sub/box.dpm\""), std::string::npos) << box;
  EXPECT_NE(box.find("\"fields\": []"), std::string::npos) << box;
  EXPECT_NE(box.find("\"parts\": [\n        {\n          \"id\": 1,"), std::string::npos) << box;
}

}  // namespace
}  // namespace dynpm
