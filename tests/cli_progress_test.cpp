// What `dynpm build` tells on stderr while it works (cli/progress.h): plain lines when stderr is
// not a terminal, JSON lines with --progress json, nothing with --quiet; and the memory
// estimate it prints before the work. (Its refusal under a memory limit: bad_input_test.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>

#include "dynpm/sanitizers.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

struct CliRun {
  int exit_code = -1;
  std::string out, err;
};

// dynpm with stdout and stderr into files of `dir` (so stderr is not a terminal).
CliRun dynpm_run(const test::TempDir& dir, const std::string& arguments) {
  const std::string out = dir.file("stdout.txt"), err = dir.file("stderr.txt");
  const int status =
      std::system((std::string(DYNPM_CLI) + " " + arguments + " >" + out + " 2>" + err).c_str());
  CliRun run;
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream o(out), e(err);
  run.out.assign(std::istreambuf_iterator<char>(o), {});
  run.err.assign(std::istreambuf_iterator<char>(e), {});
  return run;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The real crash box (CalculiX, 3,003 nodes, 26 steps), unpacked into `dir`.
std::string crashbox_frd(const test::TempDir& dir) {
  const std::string frd = dir.file("crashbox-s.frd");
  const std::string unzip =
      "zcat '" + test::shared_data() + "/crashbox-s/crashbox-s.frd.gz' > " + frd;
  return std::system(unzip.c_str()) == 0 ? frd : "";
}

// Every phase of a build, in order (auto:K reads every step to choose, then the key steps, then
// every step once more into the file's coder, then the thumbnail drawn from the build's records,
// then the file put together with it).
// The mesh is checked once, while the input is read: no "checking the mesh" of the simplifier.
const std::vector<std::string> kBuildPhases = {
    "choosing key steps", "reading key steps",  "quadrics",  "collapsing", "recording the splits",
    "coding the splits",  "encoding positions", "thumbnail", "encoding",   "writing"};

// How many digits stand between `before` at the start of `text` and `after`; 0 when the text
// is not shaped so. (By hand: std::regex trips gcc 12's -Wmaybe-uninitialized under ASan.)
size_t digits_between(const std::string& text, const std::string& before,
                      const std::string& after) {
  if (text.rfind(before, 0) != 0) return 0;
  size_t end = before.size();
  while (end < text.size() && std::isdigit(static_cast<unsigned char>(text[end]))) ++end;
  if (text.compare(end, after.size(), after) != 0) return 0;
  return end - before.size();
}

TEST(CliProgress, ARedirectedBuildPrintsALineAtTheEndOfEveryPhase) {
  test::TempDir dir;
  const std::string frd = crashbox_frd(dir);
  ASSERT_FALSE(frd.empty());
  const CliRun run = dynpm_run(dir, "build " + frd + " --key-steps auto:3 -o " + dir.file("m.dpm"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // The estimate first, then one closing line per phase, in order.
  const std::vector<std::string> lines = lines_of(run.err);
  ASSERT_FALSE(lines.empty());
  EXPECT_TRUE(digits_between(lines[0], "dynpm build: needs about ", " MB (have ") > 0 &&
              lines[0].back() == ')')
      << lines[0];
  size_t next = 0;
  for (const std::string& line : lines)
    if (next < kBuildPhases.size() &&
        line.rfind("dynpm build: " + kBuildPhases[next] + " done", 0) == 0)
      ++next;
  EXPECT_EQ(next, kBuildPhases.size()) << "phases seen in order: " << next << "\n" << run.err;
  for (const std::string& phase : kBuildPhases)  // each ends once
    EXPECT_EQ(std::count_if(lines.begin(), lines.end(),
                            [&](const std::string& l) {
                              return l.rfind("dynpm build: " + phase + " done", 0) == 0;
                            }),
              1)
        << phase << "\n"
        << run.err;
  EXPECT_EQ(run.err.find("checking the mesh"), std::string::npos) << run.err;
  // Vertices removed of the 3,003: the crash box simplifies to a small base.
  const size_t collapsing = run.err.find("collapsing done: ");
  ASSERT_NE(collapsing, std::string::npos) << run.err;
  EXPECT_EQ(digits_between(run.err.substr(collapsing), "collapsing done: ", " in"), 4) << run.err;
  // The splits are counted while they are recorded and coded (both end at the split count).
  for (const std::string phase : {"recording the splits", "coding the splits"}) {
    const size_t at = run.err.find(phase + " done: ");
    ASSERT_NE(at, std::string::npos) << run.err;
    EXPECT_EQ(digits_between(run.err.substr(at), phase + " done: ", " in"), 4) << run.err;
  }
  EXPECT_NE(run.err.find("encoding positions done: 26 in"), std::string::npos) << run.err;
  // stdout keeps its report only.
  EXPECT_EQ(run.out.find("done"), std::string::npos) << run.out;
}

// The estimate printed before the work is never below the peak resident memory the build
// reports at its end, and not far above it (build_memory_estimate(), docs/build.md): the real
// crash box (quads) with 3 key steps and with all 26, and a triangle mesh (fandisk: two faces
// per vertex); about 19–23 MB measured, mostly the program.
TEST(CliProgress, TheMemoryEstimateCoversTheBuildsPeak) {
  if (kAddressSanitizer) GTEST_SKIP() << "ASan's shadow memory is not the build's";
  test::TempDir dir;
  const std::string frd = crashbox_frd(dir);
  ASSERT_FALSE(frd.empty());
  const std::string fandisk = test::shared_data() + "/meshes/fandisk.obj";
  for (const std::string& input :
       {frd + " --key-steps auto:3", frd + " --key-steps all", "'" + fandisk + "'"}) {
    const CliRun run =
        dynpm_run(dir, "build " + input + " --progress json -o " + dir.file("m.dpm"));
    ASSERT_EQ(run.exit_code, 0) << run.err;
    unsigned long long need = 0;
    ASSERT_EQ(std::sscanf(run.err.c_str(), "{\"memory_estimate_bytes\":%llu,", &need), 1)
        << run.err;
    const size_t at = run.out.find("peak memory ");
    ASSERT_NE(at, std::string::npos) << run.out;
    const double peak_mib = std::atof(run.out.c_str() + at + 12);  // printed in 2^20 bytes
    const double need_mib = double(need) / (1 << 20);
    EXPECT_GE(need_mib, peak_mib - 0.5) << input << "\n" << run.out;
    EXPECT_LE(need_mib, 1.5 * peak_mib) << input << "\n" << run.out;
  }
}

TEST(CliProgress, QuietPrintsNothingOnStderr) {
  test::TempDir dir;
  const std::string frd = crashbox_frd(dir);
  ASSERT_FALSE(frd.empty());
  const CliRun run = dynpm_run(dir, "build " + frd + " --quiet -o " + dir.file("m.dpm"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err, "");
  EXPECT_NE(run.out.find("vertex splits rebuild the input"), std::string::npos) << run.out;
}

TEST(CliProgress, JsonLinesAreOneObjectEachWithPhaseDoneTotalElapsedAndEta) {
  test::TempDir dir;
  const std::string frd = crashbox_frd(dir);
  ASSERT_FALSE(frd.empty());
  const CliRun run = dynpm_run(
      dir, "build " + frd + " --key-steps auto:3 --progress json -o " + dir.file("m.dpm"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::vector<std::string> phases;
  int estimates = 0;
  for (const std::string& line : lines_of(run.err)) {
    // The estimate, said once: {"memory_estimate_bytes":N,"memory_available_bytes":M or null}.
    unsigned long long need = 0;
    if (std::sscanf(line.c_str(), "{\"memory_estimate_bytes\":%llu,", &need) == 1) {
      EXPECT_GT(need, 1000000u) << line;
      EXPECT_NE(line.find(",\"memory_available_bytes\":"), std::string::npos) << line;
      ++estimates;
      continue;
    }
    // {"phase":"…","done":D,"total":T,"elapsed_s":E,"eta_s":F or null}, nothing else.
    char phase[64] = {};
    unsigned long long done = 0, total = 0;
    double elapsed = 0;
    int at = -1;
    const int n = std::sscanf(line.c_str(),
                              "{\"phase\":\"%63[a-z ]\",\"done\":%llu,\"total\":%llu,"
                              "\"elapsed_s\":%lf,\"eta_s\":%n",
                              phase, &done, &total, &elapsed, &at);
    ASSERT_TRUE(n == 4 && at > 0) << line;
    const std::string eta = line.substr(static_cast<size_t>(at));
    ASSERT_TRUE(eta == "null}" || (eta.size() > 1 && eta.back() == '}' &&
                                   eta.find_first_not_of("0123456789.") == eta.size() - 1))
        << line;
    EXPECT_LE(done, total) << line;
    const std::string name = phase;
    if (name.rfind("after ", 0) == 0) continue;  // a slow stretch between two phases
    if (phases.empty() || phases.back() != name) phases.push_back(name);
  }
  EXPECT_EQ(phases, kBuildPhases);
  EXPECT_EQ(estimates, 1) << run.err;
  // A python that reads them agrees that every line is JSON, the estimate's too.
  if (const std::string python = test::python_with("json"); !python.empty()) {
    const test::CommandResult parsed = test::run_command(
        python + " -c 'import json,sys; [json.loads(l) for l in sys.stdin]; print(\"ok\")' < " +
        dir.file("stderr.txt"));
    EXPECT_EQ(parsed.output, "ok\n");
  }
}

TEST(CliProgress, AnUnknownFormIsAUsageError) {
  test::TempDir dir;
  const CliRun run = dynpm_run(dir, "build x.frd --progress loud -o " + dir.file("m.dpm"));
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("--progress takes auto, plain, json or none, got 'loud'"),
            std::string::npos)
      << run.err;
}

}  // namespace
}  // namespace dynpm
