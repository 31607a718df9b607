#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <fstream>

#include "dynpm/io.h"
#include "fixtures.h"

namespace dynpm {
namespace {

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

class PlyRoundTrip : public ::testing::TestWithParam<bool> {};

TEST_P(PlyRoundTrip, KeepsQuadsIdsAndExactPositions) {
  test::TempDir dir;
  auto m = test::tri_quad_strip();
  m.topology.part_ids = {1, 1, 2, 2};
  m.topology.element_ids = {101, 102, 9001, 9002};
  for (uint32_t v = 0; v < m.topology.vertex_count; ++v) m.topology.node_ids[v] = 500 + v;
  m.positions[1] = 0.1f;
  WriteOptions options;
  options.binary = GetParam();
  options.comment = "time 2.5";
  ASSERT_TRUE(write_mesh(dir.file("m.ply"), m.topology, m.positions, options).ok());
  auto back = read_mesh(dir.file("m.ply"));
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back->topology.faces, m.topology.faces);
  EXPECT_EQ(back->topology.part_ids, m.topology.part_ids);
  EXPECT_EQ(back->topology.element_ids, m.topology.element_ids);
  EXPECT_EQ(back->topology.node_ids, m.topology.node_ids);
  EXPECT_EQ(back->topology.quad_count(), 2u);
  auto step = back->frames.step(0);
  EXPECT_EQ(std::vector<float>(step.begin(), step.end()), m.positions);
  EXPECT_DOUBLE_EQ(back->frames.step_time(0), 2.5);
}

INSTANTIATE_TEST_SUITE_P(AsciiAndBinary, PlyRoundTrip, ::testing::Bool());

template <class T>
void append_be(std::string& out, T value) {
  char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::little) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

TEST(Ply, ReadsBigEndianDoublesAndSkipsUnknownProperties) {
  test::TempDir dir;
  std::string bytes =
      "ply\nformat binary_big_endian 1.0\ncomment written by hand\n"
      "element vertex 4\nproperty double x\nproperty double y\nproperty double z\n"
      "property uchar red\n"
      "element face 1\nproperty list uchar uint vertex_index\nproperty float quality\n"
      "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
      "end_header\n";
  const double xyz[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.5}};
  for (auto& p : xyz) {
    for (double c : p) append_be(bytes, c);
    append_be(bytes, uint8_t{200});
  }
  append_be(bytes, uint8_t{4});
  for (uint32_t i : {0u, 1u, 2u, 3u}) append_be(bytes, i);
  append_be(bytes, 0.5f);
  append_be(bytes, int32_t{0});
  append_be(bytes, int32_t{1});
  write_bytes(dir.file("be.ply"), bytes);
  auto a = read_mesh(dir.file("be.ply"));
  ASSERT_TRUE(a.ok()) << a.message();
  EXPECT_EQ(a->topology.quad_count(), 1u);
  EXPECT_EQ(a->frames.step(0)[11], 0.5f);
}

TEST(Ply, TruncatedBinaryNamesTheByteOffset) {
  test::TempDir dir;
  const auto m = test::quad_grid(3, 3);
  ASSERT_TRUE(write_mesh(dir.file("full.ply"), m.topology, m.positions).ok());
  const std::string full = read_bytes(dir.file("full.ply"));
  size_t rejected = 0;
  for (size_t cut = 0; cut < full.size(); ++cut) {
    write_bytes(dir.file("cut.ply"), full.substr(0, cut));
    auto a = read_mesh(dir.file("cut.ply"));
    EXPECT_FALSE(a.ok()) << "cut at " << cut;
    if (!a.ok()) ++rejected;
  }
  EXPECT_EQ(rejected, full.size());
  write_bytes(dir.file("cut.ply"), full.substr(0, full.size() - 3));
  auto a = read_mesh(dir.file("cut.ply"));
  EXPECT_NE(a.message().find("byte"), std::string::npos) << a.message();
  EXPECT_NE(a.message().find("truncated"), std::string::npos) << a.message();
}

TEST(Ply, HugeCountsAreRejectedBeforeAllocation) {
  test::TempDir dir;
  write_bytes(dir.file("huge.ply"),
              "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\n"
              "property float x\nproperty float y\nproperty float z\nend_header\nabc");
  auto a = read_mesh(dir.file("huge.ply"));
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.message().find("claims 1000000000000"), std::string::npos) << a.message();
}

TEST(Ply, BadHeadersAreClearErrors) {
  test::TempDir dir;
  const std::pair<const char*, const char*> cases[] = {
      {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n",
       "lacks x, y or z"},
      {"ply\nformat ascii 1.0\nelement vertex 1\n", "never ends"},
      {"ply\nformat weird 1.0\nend_header\n", "unknown PLY format"},
      {"ply\nelement vertex 1\nproperty float x\nend_header\n", "no 'format' line"},
      {"ply\nformat ascii 1.0\nelement vertex 3\nproperty quaternion x\nend_header\n",
       "unknown property type"},
      {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
       "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
       "face index 7"},
      {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
       "0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n",
       ":11: 'zero' is not a number"},
      // One number rule (text.h): counts and values are whole tokens, integers within their type.
      {"ply\nformat ascii 1.0\nelement vertex 3x\nproperty float x\nend_header\n",
       ":3: the count of element 'vertex', '3x', is not a whole number"},
      {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
       "0 0 0\n1 0 0\n0 1 0\n3 0 1 2.5\n",
       ":13: '2.5' is not a whole number"},
      {"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
       "0 0 0\n1 0 0\n0 1 0\n259 0 1 2\n",
       ":13: '259' is out of the range of its type uchar"},
      {"ply\nformat ascii 1.0\ncomment time nan\nelement vertex 1\nend_header\n",
       ":3: the time note 'nan' is not a finite number"},
  };
  for (const auto& [text, expected] : cases) {
    write_bytes(dir.file("bad.ply"), text);
    auto a = read_mesh(dir.file("bad.ply"));
    ASSERT_FALSE(a.ok()) << text;
    EXPECT_NE(a.message().find(expected), std::string::npos) << a.message();
  }
}

}  // namespace
}  // namespace dynpm
