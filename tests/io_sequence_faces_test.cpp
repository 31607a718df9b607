// A sequence's later files are checked against the first file's faces by a hash of their face
// bytes (FaceParsing::kHashOnly): the same faces written otherwise still pass, other faces fail
// with the file, the place and the face; and several threads read a sequence to the same steps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>

#include "dynpm/io.h"
#include "fixtures.h"

namespace dynpm {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// The real crash box (crashbox-s, 26 CalculiX frames) rewritten as `extension` files in `dir`.
std::vector<std::string> crashbox_as(const test::TempDir& dir, const std::string& extension,
                                     bool binary = true) {
  auto in =
      expand_inputs(std::vector<std::string>{test::shared_data() + "/crashbox-s/obj/frame_*.obj"});
  if (!in.ok()) return {};
  auto a = read_animation(*in);
  EXPECT_TRUE(a.ok()) << a.message();
  std::vector<std::string> paths;
  WriteOptions options;
  options.binary = binary;
  for (size_t t = 0; t < a->step_count(); ++t) {
    paths.push_back(*step_path(dir.file("frame_{:03d}" + extension), t));
    EXPECT_TRUE(write_mesh(paths.back(), a->topology, a->frames.step(t), options).ok());
  }
  return paths;
}

Animation read_ok(const std::vector<std::string>& paths) {
  auto a = read_animation(paths);
  EXPECT_TRUE(a.ok()) << a.message();
  return a.ok() ? std::move(a).value() : Animation{};
}

TEST(SequenceFaces, TheSameFacesWrittenOtherwisePass) {
  test::TempDir dir;
  auto paths = crashbox_as(dir, ".obj");
  if (paths.empty()) GTEST_SKIP() << "../shared/data is not beside the project";
  const Animation before = read_ok(paths);
  // Frame 7's corners as i//i and with extra blanks: other bytes (its hash differs), the same
  // faces, so it is parsed and compared face by face, and passes.
  std::string text = slurp(paths[7]), changed;
  for (size_t at = 0; at < text.size();) {
    const size_t eol = text.find('\n', at);
    std::string line = text.substr(at, eol - at);
    at = eol + 1;
    if (line.starts_with("f ")) {
      std::string out = "f ";
      size_t p = 2;
      while (p < line.size()) {
        const size_t q = std::min(line.find(' ', p), line.size());
        const std::string i = line.substr(p, q - p);
        out += " " + i + "//" + i;
        p = q + 1;
      }
      line = out;
    }
    changed += line + "\n";
  }
  ASSERT_NE(changed, text);
  std::ofstream(paths[7], std::ios::binary) << changed;
  const Animation after = read_ok(paths);
  ASSERT_EQ(after.step_count(), before.step_count());
  EXPECT_EQ(after.topology.faces, before.topology.faces);
  for (size_t t = 0; t < before.step_count(); ++t)
    EXPECT_TRUE(std::ranges::equal(after.frames.step(t), before.frames.step(t))) << t;
}

// One face of a later binary PLY rewired: the error names the file, the byte and the face.
TEST(SequenceFaces, AnotherFaceInABinaryPlyIsNamed) {
  test::TempDir dir;
  auto paths = crashbox_as(dir, ".ply");
  if (paths.empty()) GTEST_SKIP() << "../shared/data is not beside the project";
  const Animation before = read_ok(paths);
  ASSERT_EQ(before.step_count(), 26u);
  std::string bytes = slurp(paths[12]);
  // Face records: uchar 4, four int32 corners, int32 part, int32 element id (write_ply).
  const size_t body = bytes.find("end_header\n") + 11;
  const size_t vertex_record = 3 * 4 + 4;
  const size_t face_record = 1 + 4 * 4 + 4 + 4;
  const size_t face = 100;
  const size_t at = body + vertex_record * before.topology.vertex_count + face_record * face;
  ASSERT_EQ(bytes[at], 4);
  int32_t corner = 0;
  std::memcpy(&corner, &bytes[at + 1], 4);
  corner = corner == 0 ? 1 : 0;
  std::memcpy(&bytes[at + 1], &corner, 4);
  std::ofstream(paths[12], std::ios::binary) << bytes;

  auto a = read_animation(paths);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.message().find("frame_012.ply: byte " + std::to_string(at) + ": face 100 is ("),
            std::string::npos)
      << a.message();
  EXPECT_NE(a.message().find("same faces"), std::string::npos) << a.message();
}

TEST(SequenceFaces, AnotherFaceInAnAsciiPlyIsNamedByLine) {
  test::TempDir dir;
  auto paths = crashbox_as(dir, ".ply", false);
  if (paths.empty()) GTEST_SKIP() << "../shared/data is not beside the project";
  std::string text = slurp(paths[25]);
  // The last line is the last face: "4 a b c d part element".
  const size_t last = text.rfind('\n', text.size() - 2) + 1;
  const size_t line = size_t(std::count(text.begin(), text.begin() + last, '\n')) + 1;
  text.replace(last, text.size() - last, "4 0 1 2 3 1 99999\n");
  std::ofstream(paths[25], std::ios::binary) << text;
  auto a = read_animation(paths);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.message().find("frame_025.ply:" + std::to_string(line) + ": face 2936 is (0 1 2 3)"),
            std::string::npos)
      << a.message();
}

// A later file whose face block is cut short fails as a parse error, not as a hash mismatch.
TEST(SequenceFaces, ACutLaterPlyFails) {
  test::TempDir dir;
  auto paths = crashbox_as(dir, ".ply");
  if (paths.empty()) GTEST_SKIP() << "../shared/data is not beside the project";
  std::string bytes = slurp(paths[3]);
  bytes.resize(bytes.size() - 10);
  std::ofstream(paths[3], std::ios::binary) << bytes;
  auto a = read_animation(paths);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.message().find("frame_003.ply: byte"), std::string::npos) << a.message();
  EXPECT_NE(a.message().find("truncated"), std::string::npos) << a.message();
}

// Steps read through for_each_step() on one thread and on four are the same, in order.
TEST(SequenceFaces, ParallelReadsGiveTheSameSteps) {
  test::TempDir dir;
  auto paths = crashbox_as(dir, ".ply");
  if (paths.empty()) GTEST_SKIP() << "../shared/data is not beside the project";
  auto stream = open_animation(paths);
  ASSERT_TRUE(stream.ok()) << stream.message();
  const FrameSource& frames = *stream->frames;
  EXPECT_TRUE(frames.parallel_reads());
  std::vector<size_t> steps = {25, 0, 3, 4, 5, 17, 9};
  auto gather = [&](unsigned threads) {
    std::vector<std::vector<float>> seen;
    std::vector<size_t> order;
    const Status s = for_each_step(frames, steps, threads, [&](size_t i, auto xyz) {
      order.push_back(i);
      seen.emplace_back(xyz.begin(), xyz.end());
      return Status{};
    });
    EXPECT_TRUE(s.ok()) << s.message();
    EXPECT_EQ(order, (std::vector<size_t>{0, 1, 2, 3, 4, 5, 6}));
    return seen;
  };
  const auto one = gather(1), four = gather(4);
  ASSERT_EQ(one.size(), steps.size());
  EXPECT_EQ(one, four);
  std::vector<float> xyz(size_t{frames.vertex_count()} * 3);
  ASSERT_TRUE(frames.read_step(17, xyz).ok());
  EXPECT_EQ(one[5], xyz);
  EXPECT_NE(one[0], one[1]);  // the crushed last step is not the first

  // A missing file in the middle of a batch: the steps before it are used, then its error.
  std::filesystem::remove(paths[4]);
  size_t used = 0;
  const Status s = for_each_step(frames, steps, 4, [&](size_t, auto) {
    ++used;
    return Status{};
  });
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("frame_004.ply"), std::string::npos) << s.message();
  EXPECT_EQ(used, 3u);
}

}  // namespace
}  // namespace dynpm
