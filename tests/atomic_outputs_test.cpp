// Killed runs, as a user meets them on the command line.
//
// AtomicOutputs: `dynpm build` and `dynpm convert` on a generated animation, killed with SIGKILL
// at random moments (and once right as the .dpm is being written): the output is either absent
// or complete, never partial. What a killed run leaves is its temporary file, named after the
// target and the process: model.dpm.tmp-<pid>-<n>, frame_003.tmp-<pid>.ply; the next run that
// writes the same target removes it once it is a minute old.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <set>
#include <thread>

#include "dynpm/io.h"
#include "dynpm/progressive.h"
#include "dynpm/sanitizers.h"
#include "dynpm_runs.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

using test::folder_entries;
using test::joined;
using test::start_dynpm;

// ---------------------------------------------------------------------------------------------
// Atomic outputs under SIGKILL

// A wavy 80 × 80 quad grid over 6 steps, as frame_0.obj … frame_5.obj: big enough that
// `dynpm build` takes about half a second.
std::string make_animation(const test::TempDir& dir) {
  const test::Mesh grid = test::quad_grid(80, 80);
  std::vector<float> xyz = grid.positions;
  for (int t = 0; t < 6; ++t) {
    for (size_t v = 0; v < xyz.size() / 3; ++v) {
      const float x = grid.positions[v * 3], y = grid.positions[v * 3 + 1];
      xyz[v * 3 + 2] = 0.3f * float(t) * std::sin(0.2f * x) * std::cos(0.15f * y);
    }
    EXPECT_TRUE(
        write_mesh(dir.file("frame_" + std::to_string(t) + ".obj"), grid.topology, xyz).ok());
  }
  return dir.file("frame_*.obj");
}

// Waits for the process; true if it ended by itself with exit code 0.
bool finished_ok(pid_t pid) {
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

bool exists(const std::string& path) {
  std::error_code ec;
  return fs::exists(path, ec);
}

// A complete model with as many splits as the reference, or a failure naming what is wrong.
::testing::AssertionResult is_complete_model(const std::string& path, uint32_t splits) {
  auto model = read_dpm(path);
  if (!model) return ::testing::AssertionFailure() << model.message();
  if (!model->complete) return ::testing::AssertionFailure() << path << " is a prefix";
  if (model->split_count() != splits)
    return ::testing::AssertionFailure() << path << " has " << model->split_count() << " splits";
  return ::testing::AssertionSuccess();
}

// The process id in a temporary name, "<target>.tmp-<pid>-<n>" or "<stem>.tmp-<pid><ext>";
// -1 if the name is no temporary one. (Parsed by hand: std::regex trips gcc 12's
// maybe-uninitialized warning under -fsanitize=address.)
long temporary_owner(const std::string& name) {
  const size_t at = name.rfind(".tmp-");
  if (at == std::string::npos) return -1;
  size_t end = at + 5;
  while (end < name.size() && name[end] >= '0' && name[end] <= '9') ++end;
  if (end == at + 5) return -1;
  return std::stol(name.substr(at + 5, end - at - 5));
}

// What killed processes may leave beside their targets: their own temporary files, only.
void expect_only_own_temporaries(const fs::path& dir, const std::set<std::string>& keep,
                                 const std::set<pid_t>& killed) {
  for (const std::string& name : folder_entries(dir)) {
    if (keep.count(name)) continue;
    const long owner = temporary_owner(name);
    ASSERT_GE(owner, 0) << "unexpected file " << name;
    EXPECT_TRUE(killed.count(static_cast<pid_t>(owner))) << name << " is no killed run's";
    fs::remove(dir / name);
  }
}

// Sets every temporary file in dir back by two minutes, as if the kills were that long ago;
// how many there are.
int age_temporaries(const fs::path& dir) {
  int n = 0;
  for (const std::string& name : folder_entries(dir)) {
    if (temporary_owner(name) < 0) continue;
    fs::last_write_time(dir / name, fs::last_write_time(dir / name) - std::chrono::minutes(2));
    ++n;
  }
  return n;
}

int count_temporaries(const fs::path& dir) {
  int n = 0;
  for (const std::string& name : folder_entries(dir)) n += temporary_owner(name) >= 0;
  return n;
}

// The id of a process that has ended (and been reaped): no process has it now.
pid_t ended_process() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  ::waitpid(pid, nullptr, 0);
  return pid;
}

// Which leftovers a write removes: only its own target's temporaries, only of processes gone
// from this machine, only when a minute old.
TEST(AtomicOutputs, StaleTemporariesOfEndedRunsAreRemoved) {
  test::TempDir dir;
  const std::string ended = std::to_string(ended_process());
  const std::string alive = std::to_string(::getppid());  // the test runner's parent
  auto plant = [&](const std::string& name, bool old) {
    std::ofstream(dir.file(name)) << "partial";
    if (old)
      fs::last_write_time(dir.file(name),
                          fs::file_time_type::clock::now() - std::chrono::minutes(2));
  };
  plant("model.dpm.tmp-" + ended + "-0", true);                    // removed
  plant("model.tmp-" + ended + ".dpm", true);                      // removed (the staged form)
  plant("model.tmp-" + ended + ".dpm.tmp-" + ended + "-3", true);  // removed (its own temporary)
  plant("model.dpm.tmp-" + ended + "-1", false);                   // kept: too recent
  plant("model.dpm.tmp-" + alive + "-0", true);                    // kept: its process runs
  plant("other.dpm.tmp-" + ended + "-0", true);                    // kept: another target's
  plant("model.dpm.tmp-" + ended + "-x", true);  // kept: not a temporary name of ours
  plant("model.dpm.tmp-" + ended, true);         // kept: not a temporary name of ours
  plant("model.tmp-" + ended + ".dpmx", true);   // kept: not a temporary name of ours
  ASSERT_TRUE(write_file_atomically(dir.file("model.dpm"), "complete").ok());
  std::vector<std::string> kept = {"model.dpm",
                                   "model.dpm.tmp-" + alive + "-0",
                                   "model.dpm.tmp-" + ended,
                                   "model.dpm.tmp-" + ended + "-1",
                                   "model.dpm.tmp-" + ended + "-x",
                                   "model.tmp-" + ended + ".dpmx",
                                   "other.dpm.tmp-" + ended + "-0"};
  std::sort(kept.begin(), kept.end());
  EXPECT_EQ(joined(folder_entries(dir.path())), joined(kept));
  EXPECT_EQ(remove_stale_temporaries(dir.file("model.dpm")), 0u);
  EXPECT_EQ(remove_stale_temporaries(dir.file("other.dpm")), 1u);
}

// A multi-file output (one file per step) lists its folder once for all its targets, not once
// per file: 10,000 steps made 10,000 listings of a folder that grew to 10,000 files (94 s).
TEST(AtomicOutputs, AMultiFileOutputListsItsFolderOnce) {
  test::TempDir dir;
  const std::string ended = std::to_string(ended_process());
  std::vector<std::string> targets;
  for (int k = 0; k < 1000; ++k) targets.push_back(dir.file("s_" + std::to_string(k) + ".obj"));
  auto plant = [&](const std::string& name) {
    std::ofstream(dir.file(name)) << "partial";
    fs::last_write_time(dir.file(name), fs::file_time_type::clock::now() - std::chrono::minutes(2));
  };
  plant("s_7.tmp-" + ended + ".obj");                        // a staged step file
  plant("s_500.tmp-" + ended + ".obj.tmp-" + ended + "-0");  // its own temporary
  plant("s_999.obj.tmp-" + ended + "-3");                    // a single file's temporary
  plant("t_1.tmp-" + ended + ".obj");                        // kept: no target's
  const size_t scans = stale_temporary_scans();
  EXPECT_EQ(remove_stale_temporaries(targets), 3u);
  EXPECT_EQ(stale_temporary_scans() - scans, 1u);
  EXPECT_EQ(joined(folder_entries(dir.path())), joined({"t_1.tmp-" + ended + ".obj"}));

  // Writing a staged file of this process (what StagedOutputs hands to the mesh writers) lists
  // nothing: its target's one listing covers its leftovers.
  const std::string staged = dir.file("s_1.tmp-" + std::to_string(::getpid()) + ".obj");
  const size_t before = stale_temporary_scans();
  ASSERT_TRUE(write_file_atomically(staged, "v 0 0 0\n").ok());
  EXPECT_EQ(stale_temporary_scans(), before);
  ASSERT_TRUE(write_file_atomically(dir.file("model.dpm"), "complete").ok());
  EXPECT_EQ(stale_temporary_scans(), before + 1);
}

TEST(AtomicOutputs, AKilledBuildLeavesNoPartialModel) {
  test::TempDir dir;
  const std::string input = make_animation(dir);
  const std::string model = dir.file("model.dpm");

  // Runs to the end: how long a build takes here (the fastest of three: the first pays for cold
  // caches, and kill moments drawn from a slow run let most builds finish), and what a complete
  // model holds.
  double full_ms = 1e300;
  for (int run = 0; run < 3; ++run) {
    const auto start = Clock::now();
    ASSERT_TRUE(finished_ok(start_dynpm({"build", input, "-o", model})));
    full_ms =
        std::min(full_ms, std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  }
  auto reference = read_dpm(model);
  ASSERT_TRUE(reference.ok()) << reference.message();
  const uint32_t splits = reference->split_count();
  fs::copy_file(model, dir.file("reference.dpm"));

  const unsigned seed = std::random_device{}();
  SCOPED_TRACE("seed " + std::to_string(seed) + ", a full build takes " +
               std::to_string(int(full_ms)) + " ms");
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> moment(0.0, 1.1 * full_ms);

  std::set<pid_t> killed;
  int kills = 0, completed = 0;
  // Random moments: half with no model yet (it appears, complete, or not at all), half with a
  // complete model from before in place (it stays complete).
  for (int trial = 0; trial < 8; ++trial) {
    const bool fresh = trial % 2 == 0;
    if (fresh)
      fs::remove(model);
    else
      fs::copy_file(dir.file("reference.dpm"), model, fs::copy_options::overwrite_existing);
    const pid_t pid = start_dynpm({"build", input, "-o", model});
    std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(moment(random)));
    ::kill(pid, SIGKILL);
    if (finished_ok(pid)) {
      ++completed;
    } else {
      ++kills;
      killed.insert(pid);
    }
    if (fresh && !exists(model)) continue;
    EXPECT_TRUE(is_complete_model(model, splits)) << "trial " << trial;
  }

  // While writing: as soon as the temporary file appears (opened, the bytes on their way), and
  // as soon as it holds bytes (written, being synced to disk before the rename). Both windows
  // are short (≈ 0.1 ms and the fsync's few ms on ext4), so each gets up to three attempts.
  std::string caught_sizes;
  int caught_count = 0;
  for (const bool wait_for_bytes : {false, true}) {
    for (int attempt = 0; attempt < 3; ++attempt) {
      fs::remove(model);
      const pid_t pid = start_dynpm({"build", input, "-o", model});
      const std::string temp = model + ".tmp-" + std::to_string(pid) + "-0";
      auto ready = [&] {
        std::error_code ec;
        const auto size = fs::file_size(temp, ec);
        return !ec && (!wait_for_bytes || size > 0);
      };
      const auto give_up = Clock::now() + std::chrono::milliseconds(int(20 * full_ms) + 5000);
      while (!ready() && !exists(model) && Clock::now() < give_up) std::this_thread::yield();
      ::kill(pid, SIGKILL);
      if (finished_ok(pid)) {
        ++completed;
      } else {
        ++kills;
        killed.insert(pid);
      }
      if (exists(model)) {  // it finished first
        EXPECT_TRUE(is_complete_model(model, splits));
        continue;
      }
      // A killed run leaves its temporary file, under a name that says whose it is.
      ASSERT_TRUE(exists(temp)) << "neither " << model << " nor " << temp;
      caught_sizes += " " + std::to_string(fs::file_size(temp));
      ++caught_count;
      break;
    }
  }
  std::printf(
      "[ killed    ] %d builds killed, %d finished first; seed %u, %.0f ms a build; %d killed "
      "while writing, their temporary files held%s of %ju bytes\n",
      kills, completed, seed, full_ms, caught_count, caught_sizes.c_str(),
      std::uintmax_t(fs::file_size(dir.file("reference.dpm"))));
  EXPECT_GE(caught_count, 1) << "no kill came while the model was being written";
  EXPECT_GE(kills, 5);

  // What the killed runs left, a minute later: the next build removes it.
  const int left = age_temporaries(dir.path());
  EXPECT_GE(left, caught_count);
  ASSERT_TRUE(finished_ok(start_dynpm({"build", input, "-o", model})));
  EXPECT_EQ(count_temporaries(dir.path()), 0) << left << " left by killed builds";
  EXPECT_TRUE(is_complete_model(model, splits));
  expect_only_own_temporaries(dir.path(),
                              {"model.dpm", "reference.dpm", "frame_0.obj", "frame_1.obj",
                               "frame_2.obj", "frame_3.obj", "frame_4.obj", "frame_5.obj"},
                              killed);
}

// convert writes one file per step, staged and renamed at the end: a kill leaves each step's
// file either absent or complete.
TEST(AtomicOutputs, AKilledConvertLeavesOnlyCompleteFiles) {
  test::TempDir dir;
  const std::string input = make_animation(dir);
  fs::create_directory(dir.path() / "out");
  const std::string pattern = dir.file("out/copy_{}.ply");

  const auto start = Clock::now();
  ASSERT_TRUE(finished_ok(start_dynpm({"convert", input, "-o", pattern})));
  const double full_ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  std::vector<std::string> reference;
  for (int t = 0; t < 6; ++t) {
    auto bytes = read_file(dir.file("out/copy_" + std::to_string(t) + ".ply"));
    ASSERT_TRUE(bytes.ok());
    reference.push_back(*bytes);
  }

  const unsigned seed = std::random_device{}();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> moment(0.0, 1.1 * full_ms);
  std::set<pid_t> killed;
  for (int trial = 0; trial < 5; ++trial) {
    fs::remove_all(dir.path() / "out");
    fs::create_directory(dir.path() / "out");
    const pid_t pid = start_dynpm({"convert", input, "-o", pattern});
    std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(moment(random)));
    ::kill(pid, SIGKILL);
    if (!finished_ok(pid)) killed.insert(pid);
    for (int t = 0; t < 6; ++t) {
      const std::string path = dir.file("out/copy_" + std::to_string(t) + ".ply");
      if (!exists(path)) continue;
      auto bytes = read_file(path);
      ASSERT_TRUE(bytes.ok());
      EXPECT_EQ(*bytes == reference[t], true) << path << " differs from a complete run's";
    }
    std::set<std::string> keep;
    for (int t = 0; t < 6; ++t) keep.insert("copy_" + std::to_string(t) + ".ply");
    expect_only_own_temporaries(dir.path() / "out", keep, killed);
  }

  // The staged files of a killed convert go with the next convert to the same names. Killed as
  // soon as its first staged file appears.
  int left = 0;
  for (int trial = 0; trial < 5 && left == 0; ++trial) {
    const pid_t pid = start_dynpm({"convert", input, "-o", pattern});
    const auto give_up = Clock::now() + std::chrono::milliseconds(int(20 * full_ms) + 5000);
    while (count_temporaries(dir.path() / "out") == 0 && Clock::now() < give_up)
      std::this_thread::yield();
    ::kill(pid, SIGKILL);
    finished_ok(pid);
    left = age_temporaries(dir.path() / "out");
  }
  ASSERT_GT(left, 0) << "no kill left a staged file";
  ASSERT_TRUE(finished_ok(start_dynpm({"convert", input, "-o", pattern})));
  EXPECT_EQ(count_temporaries(dir.path() / "out"), 0) << left << " left by a killed convert";
}

}  // namespace
}  // namespace dynpm
