// Bad inputs, as a user meets them on the command line.
//
// BadInputs: every line of tests/bad/expected.txt — a broken file, a command, the exit code and
// the exact message dynpm must give — run through the dynpm binary; a failed run must leave
// nothing in its output folder (no output, no temporary file).
//
// Memory: what a file can make dynpm allocate (a decompression bomb is refused before its memory),
// and running out of it: a message and exit 1, no output left.
// (Killed runs: atomic_outputs_test.cpp.)
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

using test::argv_of;
using test::dynpm_command;
using test::folder_entries;
using test::joined;

std::string bad_dir() { return test::source_dir() + "/tests/bad"; }

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t") - a + 1);
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
  return s;
}

// One line of expected.txt: input | verb and options | exit code | message.
struct Expectation {
  int line = 0;
  std::string input, verb, options, message;
  int exit_code = -1;
};

std::vector<Expectation> read_manifest() {
  std::ifstream in(bad_dir() + "/expected.txt");
  std::vector<Expectation> entries;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    if (trim(text).empty() || trim(text)[0] == '#') continue;
    std::vector<std::string> fields;
    size_t start = 0;
    for (int k = 0; k < 3; ++k) {  // the message, last, may hold anything
      const size_t bar = text.find('|', start);
      if (bar == std::string::npos) break;
      fields.push_back(trim(text.substr(start, bar - start)));
      start = bar + 1;
    }
    fields.push_back(trim(text.substr(start)));
    Expectation e;
    e.line = line;
    if (fields.size() != 4) {  // reported by the test, not skipped
      entries.push_back(e);
      continue;
    }
    e.input = fields[0];
    const size_t space = fields[1].find(' ');
    e.verb = fields[1].substr(0, space);
    e.options = space == std::string::npos ? "" : fields[1].substr(space + 1);
    e.exit_code = std::atoi(fields[2].c_str());
    e.message = fields[3];
    entries.push_back(e);
  }
  return entries;
}

bool is_temporary(const std::string& name) { return name.find(".tmp-") != std::string::npos; }

TEST(BadInputs, TheManifestCoversEveryCorpusFile) {
  const auto entries = read_manifest();
  ASSERT_FALSE(entries.empty()) << "no entries in " << bad_dir() << "/expected.txt";
  std::set<std::string> with_info, with_build;
  for (const Expectation& e : entries) {
    ASSERT_FALSE(e.input.empty()) << "expected.txt:" << e.line << ": needs 4 fields separated by |";
    ASSERT_TRUE(e.exit_code >= 0 && e.exit_code <= 3) << "expected.txt:" << e.line;
    ASSERT_FALSE(e.message.empty()) << "expected.txt:" << e.line;
    if (e.verb == "info") with_info.insert(e.input);
    if (e.verb == "build") with_build.insert(e.input);
  }
  for (const Expectation& e : entries) {
    EXPECT_TRUE(with_info.count(e.input)) << e.input << " has no info line";
    EXPECT_TRUE(with_build.count(e.input)) << e.input << " has no build line";
  }
  // Every file or folder of the corpus is some line's input (or holds it).
  for (const std::string& name : folder_entries(bad_dir())) {
    if (name == "README.md" || name == "expected.txt" || name == "make_corpus.py" ||
        name == "__pycache__")
      continue;
    const bool used = std::any_of(entries.begin(), entries.end(), [&](const Expectation& e) {
      return e.input == name || e.input.starts_with(name + "/");
    });
    EXPECT_TRUE(used) << "tests/bad/" << name << " is in no line of expected.txt";
  }
}

TEST(BadInputs, EveryFileGivesItsExitCodeAndExactMessage) {
  const auto entries = read_manifest();
  ASSERT_FALSE(entries.empty());
  for (const Expectation& e : entries) {
    if (e.input.empty()) continue;  // reported by TheManifestCoversEveryCorpusFile
    SCOPED_TRACE("tests/bad/expected.txt:" + std::to_string(e.line) + ": dynpm " + e.verb + " " +
                 e.input);
    test::TempDir out;
    const std::string command = "cd '" + bad_dir() + "' && '" + DYNPM_CLI + "' " + e.verb + " '" +
                                e.input + "' " + replace_all(e.options, "{out}", out.path());
    const auto r = test::run_command(command);
    EXPECT_EQ(r.exit_code, e.exit_code) << r.output;
    const std::string message = replace_all(e.message, "{out}", out.path());
    EXPECT_NE(r.output.find(message), std::string::npos)
        << "expected: " << message << "\ngot:      " << r.output;
    const auto left = folder_entries(out.path());
    if (e.exit_code == 1 || e.exit_code == 2) {
      EXPECT_TRUE(left.empty()) << "a failed run left " << joined(left);
    } else {
      EXPECT_TRUE(std::none_of(left.begin(), left.end(), is_temporary))
          << "temporary files left: " << joined(left);
    }
    if (e.exit_code == 0 && e.verb == "build") {
      auto model = read_dpm(out.file("model.dpm"));
      ASSERT_TRUE(model.ok()) << model.message();
      EXPECT_TRUE(model->complete);
    }
  }
}

// Steps 0 and 1 of a sequence convert, step 2 does not: the files of an earlier run survive.
TEST(BadInputs, AFailedRunKeepsTheFilesItWouldHaveReplaced) {
  test::TempDir out;
  std::ofstream(out.file("copy_000.ply")) << "an earlier run's file\n";
  const auto r =
      test::run_command("cd '" + bad_dir() + "' && '" + DYNPM_CLI +
                        "' convert 'seq-faces/frame_*.obj' -o " + out.file("copy_{:03d}.ply"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(folder_entries(out.path()), std::vector<std::string>{"copy_000.ply"});
  std::ifstream in(out.file("copy_000.ply"));
  std::string first;
  std::getline(in, first);
  EXPECT_EQ(first, "an earlier run's file");
}

// validate()'s zero-area rule: a triangle on a line, a quad folded onto a segment; each face
// once, at the first step where it is flat.
TEST(BadInputs, ZeroAreaFacesAreAWarningOncePerFace) {
  test::Mesh m = test::quad_grid(2, 1);  // 0-1-2 / 3-4-5, quads (0 1 4 3) and (1 2 5 4)
  Animation a = m.animation();
  std::vector<float> flat = m.positions;
  for (int k : {3, 4, 5}) flat[k * 3 + 1] = 0;  // step 1: the top row lies on the bottom row
  a.frames.add_step(flat, 1.0);
  a.frames.add_step(flat, 2.0);
  const ValidationReport report = validate(a);
  EXPECT_TRUE(report.ok());
  EXPECT_EQ(report.count(ProblemKind::kZeroAreaFace), 2u);
  for (const Problem& p : report.problems)
    if (p.kind == ProblemKind::kZeroAreaFace) {
      EXPECT_EQ(p.severity, Severity::kWarning);
      EXPECT_EQ(p.step, 1u) << p.message;
    }

  test::Mesh sliver = test::tri_quad_strip();
  sliver.positions[7 * 3 + 1] = 0.5f;  // vertex 7 onto the line through 2 and 6: tri 2-7-6 flat
  sliver.positions[7 * 3 + 0] = 2.5f;
  sliver.positions[6 * 3 + 0] = 3.0f;
  sliver.positions[2 * 3 + 0] = 2.0f;
  const ValidationReport r2 = validate(sliver.animation());
  ASSERT_EQ(r2.count(ProblemKind::kZeroAreaFace), 1u);
  for (const Problem& p : r2.problems) {
    if (p.kind == ProblemKind::kZeroAreaFace) {
      EXPECT_EQ(p.face, 2u) << p.message;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Memory: what a file can make dynpm allocate, and what running out of it does

struct MeasuredRun {
  int exit_code = -1;
  std::string output;  // stdout and stderr
  long peak_mb = 0;    // the process's own peak resident memory (wait4), no other child's
};

// dynpm with these arguments in `folder`, its address space limited to limit_mb when > 0.
MeasuredRun run_measured(const std::string& folder, const std::vector<std::string>& arguments,
                         long limit_mb = 0) {
  test::TempDir scratch;
  const std::string log = scratch.file("output.txt");
  std::vector<std::string> args = dynpm_command(arguments);
  std::vector<char*> argv = argv_of(args);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int out = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(out, STDOUT_FILENO);
    ::dup2(out, STDERR_FILENO);
    if (::chdir(folder.c_str()) != 0) ::_exit(126);
    if (limit_mb > 0) {
      const rlimit limit{rlim_t(limit_mb) << 20, rlim_t(limit_mb) << 20};
      ::setrlimit(RLIMIT_AS, &limit);
    }
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  MeasuredRun run;
  int status = 0;
  rusage usage{};
  ::wait4(pid, &status, 0, &usage);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.peak_mb = usage.ru_maxrss / 1024;  // kB on Linux
  std::ifstream in(log);
  run.output.assign(std::istreambuf_iterator<char>(in), {});
  return run;
}

// bomb-base.dpm: 64 KiB whose BASE chunk holds a zstd frame of 2^31 zero bytes (make_corpus.py).
// It is refused from its chunk header, before a byte is allocated for it: reading it took 2.1 GB.
TEST(BadInputs, ADecompressionBombIsRefusedBeforeItsMemory) {
  test::TempDir out;
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"info", "bomb-base.dpm"},
        std::vector<std::string>{"extract", "bomb-base.dpm", "--full", "--step", "0", "-o",
                                 out.file("level.obj")}}) {
    SCOPED_TRACE(args[0]);
    const MeasuredRun run = run_measured(bad_dir(), args);
    EXPECT_EQ(run.exit_code, 1) << run.output;
    EXPECT_NE(run.output.find("bomb-base.dpm: byte "), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("the BASE chunk claims 2147483648 bytes"), std::string::npos)
        << run.output;
    EXPECT_LT(run.peak_mb, 200) << "peak resident memory in MB";
  }
}

// claims-30m-vertices.dpm: 365 bytes whose HEAD claims 30 million vertices and faces. What the
// reader keeps grows with the splits that arrive: it took 375 MB and 1 s (300 million: 3.6 GB
// and 10 s; 4 billion: 12.5 GB and over a minute) before the file was refused where it ends.
TEST(BadInputs, AHeaderThatClaimsMillionsCostsOnlyWhatArrives) {
  test::TempDir out;
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"info", "claims-30m-vertices.dpm"},
        std::vector<std::string>{"extract", "claims-30m-vertices.dpm", "--full", "--step", "0",
                                 "-o", out.file("level.obj")}}) {
    SCOPED_TRACE(args[0]);
    const MeasuredRun run = run_measured(bad_dir(), args);
    EXPECT_EQ(run.exit_code, 1) << run.output;
    EXPECT_NE(run.output.find("END after 6 of 29999997 splits"), std::string::npos) << run.output;
    EXPECT_LT(run.peak_mb, 200) << "peak resident memory in MB";
  }
}

// Out of memory is a message and exit 1 that names the phase, not "terminate called after
// throwing std::bad_alloc" (exit 134); nothing is left in the output folder.
TEST(AtomicOutputs, OutOfMemoryIsAMessageAndLeavesNoOutput) {
  if (kAddressSanitizer) GTEST_SKIP() << "ASan reserves terabytes of address space: no ulimit -v";
  // 350 × 350 quads over 4 steps: dynpm starts in about 70 MB of address space (its shared
  // libraries), reads this in 96 MB, and needs about 130 MB to simplify it.
  test::TempDir dir;
  const test::Mesh grid = test::quad_grid(350, 350);
  std::vector<float> xyz = grid.positions;
  for (int t = 0; t < 4; ++t) {
    for (size_t v = 0; v < xyz.size() / 3; ++v)
      xyz[v * 3 + 2] = 0.3f * float(t) * std::sin(0.2f * grid.positions[v * 3]);
    ASSERT_TRUE(
        write_mesh(dir.file("frame_" + std::to_string(t) + ".ply"), grid.topology, xyz).ok());
  }
  test::TempDir out;
  const std::string model = out.file("model.dpm");
  // Past the estimate's refusal (the next test), into the allocation that fails.
  const MeasuredRun run = run_measured(
      dir.path(), {"build", dir.file("frame_*.ply"), "--no-memory-check", "-o", model}, 96);
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("dynpm build: out of memory while "), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("address-space limit 96 MB"), std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("terminate called"), std::string::npos) << run.output;
  EXPECT_EQ(joined(folder_entries(out.path())), "[]");
}

// Under a memory limit the build refuses before the work, from its estimate: exit 1, the memory
// it needs and has, and no output. The real mixed crash box (4,929 nodes, 41 steps, all of them
// key steps: about 28 MB by the estimate), run as a user would: bash -c 'ulimit -v N; dynpm build'.
// dynpm has used about 66 MB of address space once it has read it; 82 MB leave it about 16.
TEST(AtomicOutputs, ABuildThatCannotFitIsRefusedUpFrontWithItsEstimate) {
  if (kAddressSanitizer) GTEST_SKIP() << "ASan reserves terabytes of address space: no ulimit -v";
  test::TempDir dir;
  const std::string frd = dir.file("crashbox-mixed-5k.frd");
  ASSERT_EQ(std::system(("zcat '" + test::shared_data() +
                         "/crashbox-mixed-5k/crashbox-mixed-5k.frd.gz' > " + frd)
                            .c_str()),
            0);
  test::TempDir out;
  const std::string model = out.file("model.dpm");
  const std::string build = std::string(DYNPM_CLI) + " build " + frd + " -o " + model;
  const std::string log = dir.file("log.txt");
  const std::string command = "bash -c 'ulimit -v 84000; " + build + "' >" + log + " 2>&1";
  const int status = std::system(command.c_str());
  std::ifstream in(log);
  const std::string output(std::istreambuf_iterator<char>(in), {});
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1) << output;
  EXPECT_NE(output.find("dynpm build: needs about "), std::string::npos) << output;
  EXPECT_NE(output.find(", have "), std::string::npos) << output;
  EXPECT_EQ(output.find("out of memory"), std::string::npos) << output;
  EXPECT_EQ(joined(folder_entries(out.path())), "[]");
}

// Where no thread can be started (here each thread's stack, 3 GB by ulimit -s, does not fit in
// the 2.5 GB ulimit -v leaves), the build does on one thread what it does on several — the faces'
// check, which otherwise runs beside the key steps' choice, included — and writes the same file.
TEST(AtomicOutputs, ABuildWithNoThreadToBeHadWritesTheSameFile) {
  if (kAddressSanitizer) GTEST_SKIP() << "ASan reserves terabytes of address space: no ulimit -v";
  test::TempDir dir;
  const std::string frd = dir.file("crashbox-s.frd");
  ASSERT_EQ(
      std::system(
          ("zcat '" + test::shared_data() + "/crashbox-s/crashbox-s.frd.gz' > " + frd).c_str()),
      0);
  const std::string build = std::string(DYNPM_CLI) + " build " + frd + " --quiet -o ";
  ASSERT_EQ(std::system((build + dir.file("threads.dpm") + " > /dev/null").c_str()), 0);
  const std::string log = dir.file("log.txt");
  const int status = std::system(("bash -c 'ulimit -v 2500000; ulimit -s 3000000; " + build +
                                  dir.file("none.dpm") + "' > " + log + " 2>&1")
                                     .c_str());
  std::ifstream in(log);
  const std::string output(std::istreambuf_iterator<char>(in), {});
  ASSERT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 0) << output;
  std::ifstream a(dir.file("threads.dpm"), std::ios::binary),
      b(dir.file("none.dpm"), std::ios::binary);
  const std::string with_threads(std::istreambuf_iterator<char>(a), {}),
      without(std::istreambuf_iterator<char>(b), {});
  EXPECT_GT(with_threads.size(), 1000u);
  EXPECT_TRUE(with_threads == without);
}

}  // namespace
}  // namespace dynpm
