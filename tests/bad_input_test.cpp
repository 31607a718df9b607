// Bad inputs, as a user meets them on the command line.
//
// BadInputs: every line of tests/bad/expected.txt — a broken file, a command, the exit code and
// the exact message dynpm must give — run through the dynpm binary; a failed run must leave
// nothing in its output folder (no output, no temporary file).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include "dynpm/io.h"
#include "dynpm/progressive.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

namespace fs = std::filesystem;

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

std::vector<std::string> folder_entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return "[" + s + "]";
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
    EXPECT_NE(r.output.find(e.message), std::string::npos)
        << "expected: " << e.message << "\ngot:      " << r.output;
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

}  // namespace
}  // namespace dynpm
