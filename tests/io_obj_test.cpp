#include <gtest/gtest.h>

#include <fstream>

#include "dynpm/io.h"
#include "fixtures.h"

namespace dynpm {
namespace {

void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

TEST(Obj, RoundTripKeepsQuadsTrianglesPartsAndExactPositions) {
  test::TempDir dir;
  auto m = test::tri_quad_strip();
  m.topology.part_ids = {3, 3, 8, 8};
  m.positions[4] = 0.1f;  // a value without a short decimal form
  m.positions[9] = -1.0e-7f;
  ASSERT_TRUE(write_mesh(dir.file("m.obj"), m.topology, m.positions).ok());
  auto back = read_mesh(dir.file("m.obj"));
  ASSERT_TRUE(back.ok()) << back.message();
  EXPECT_EQ(back->topology.faces, m.topology.faces);
  EXPECT_EQ(back->topology.part_ids, m.topology.part_ids);
  EXPECT_EQ(back->topology.quad_count(), 2u);
  EXPECT_EQ(back->topology.triangle_count(), 2u);
  auto step = back->frames.step(0);
  EXPECT_EQ(std::vector<float>(step.begin(), step.end()), m.positions);  // bit-exact
}

TEST(Obj, ReadsTheCommonFaceFormsNegativeIndicesCommentsAndCrlf) {
  test::TempDir dir;
  write_text(dir.file("forms.obj"),
             "# a comment\r\n"
             "mtllib none.mtl\r\n"
             "v 0 0 0\r\nv 1 0 0\r\nv 1 1 0\r\nv 0 1 0\r\nv 2 0 0\r\nv 2 1 0\r\n"
             "vt 0 0\r\nvn 0 0 1\r\n"
             "g panel\r\n"
             "f 1/1/1 2/1/1 3/1/1 4/1/1\r\n"
             "usemtl steel\r\n"
             "g part_12\r\n"
             "f 2//1 5//1 6//1\r\n"
             "f -5 -1 -4\r\n"  // 2 6 3
             "s off\r\n");
  auto a = read_mesh(dir.file("forms.obj"));
  ASSERT_TRUE(a.ok()) << a.message();
  const Topology& t = a->topology;
  ASSERT_EQ(t.faces.size(), 3u);
  EXPECT_EQ(t.faces[0], (Face{{0, 1, 2, 3}}));
  EXPECT_EQ(t.faces[1], (Face{{1, 4, 5, kNoVertex}}));
  EXPECT_EQ(t.faces[2], (Face{{1, 5, 2, kNoVertex}}));
  EXPECT_EQ(t.part_ids, (std::vector<int32_t>{1, 12, 12}));  // "panel" gets the first free id
  EXPECT_EQ(t.vertex_count, 6u);
  EXPECT_EQ(t.node_ids.back(), 6);
}

TEST(Obj, TimeIsTakenFromTheHeaderComment) {
  test::TempDir dir;
  write_text(dir.file("t.obj"),
             "# cb5.frd frame 3: time 0.12 (frd block 3)\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  auto a = read_mesh(dir.file("t.obj"));
  ASSERT_TRUE(a.ok());
  EXPECT_DOUBLE_EQ(a->frames.step_time(0), 0.12);
}

TEST(Obj, PolygonsNeedTheSplitOption) {
  test::TempDir dir;
  write_text(dir.file("penta.obj"), "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4 5\n");
  auto refused = read_mesh(dir.file("penta.obj"));
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("penta.obj:6"), std::string::npos) << refused.message();
  EXPECT_NE(refused.message().find("5 corners"), std::string::npos);

  std::vector<std::string> warnings;
  ReadOptions split;
  split.split_polygons = true;
  split.warn = [&](const std::string& w) { warnings.push_back(w); };
  auto a = read_mesh(dir.file("penta.obj"), split);
  ASSERT_TRUE(a.ok()) << a.message();
  EXPECT_EQ(a->topology.triangle_count(), 3u);
  EXPECT_EQ(warnings.size(), 1u);
  EXPECT_TRUE(validate(*a).ok());
}

struct BadObj {
  const char* name;
  const char* text;
  const char* expected;  // part of the error message
};

class ObjRejects : public ::testing::TestWithParam<BadObj> {};

TEST_P(ObjRejects, WithFileLineAndCause) {
  test::TempDir dir;
  const BadObj& bad = GetParam();
  const std::string path = dir.file(std::string(bad.name) + ".obj");
  write_text(path, bad.text);
  auto a = read_mesh(path);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.message().find(path), std::string::npos) << a.message();
  EXPECT_NE(a.message().find(bad.expected), std::string::npos) << a.message();
}

INSTANTIATE_TEST_SUITE_P(
    Bad, ObjRejects,
    ::testing::Values(
        BadObj{"empty", "", "empty"},
        BadObj{"truncated_vertex", "v 0 0 0\nv 1 0 0\nv 1 1", ":3: a vertex needs three numbers"},
        BadObj{"truncated_face", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2", ":4: a face needs at least 3"},
        BadObj{"index_zero", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 0 1 2\n", ":4: face index 0"},
        BadObj{"out_of_range", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 4\n", ":4: face index 4 is past"},
        BadObj{"relative_too_far", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\n", ":3: relative index -3"},
        BadObj{"bad_corner", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 x\n", ":4: face corner 'x' is not"},
        // One number rule (text.h): a whole token, for coordinates and corners alike.
        BadObj{"junk_after_coordinate", "v 0 0 0\nv 1 0 0x\n", ":2: vertex coordinate '0x'"},
        BadObj{"junk_after_corner", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3x\n",
               ":4: face corner '3x' is not"},
        BadObj{"time_note_inf", "# time inf\nv 0 0 0\n", ":1: the time note 'inf' is not a finite"},
        BadObj{"no_faces", "v 0 0 0\n", "no faces"},
        BadObj{"garbage",
               "\x7f"
               "ELF\x02\x01\x01\x00\x00garbage",
               ":1: binary data"}),
    [](const ::testing::TestParamInfo<BadObj>& param) { return std::string(param.param.name); });

TEST(Obj, MissingFileAndDirectoryAreClearErrors) {
  test::TempDir dir;
  auto missing = read_mesh(dir.file("nope.obj"));
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("cannot open"), std::string::npos);
  std::filesystem::create_directory(dir.file("folder.obj"));
  auto folder = read_mesh(dir.file("folder.obj"));
  ASSERT_FALSE(folder.ok());
  EXPECT_NE(folder.message().find("is a directory"), std::string::npos);
}

TEST(Obj, EveryTruncationOfARealFileIsReadOrRejectedWithoutCrashing) {
  const std::string path = test::shared_data() + "/crashbox-s/obj/frame_010.obj";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "../shared/data is not beside the project";
  std::ifstream in(path, std::ios::binary);
  const std::string full((std::istreambuf_iterator<char>(in)), {});
  test::TempDir dir;
  size_t rejected = 0;
  for (size_t cut = 0; cut < full.size(); cut += full.size() / 97 + 1) {
    write_text(dir.file("cut.obj"), full.substr(0, cut));
    auto a = read_mesh(dir.file("cut.obj"));
    if (!a.ok()) {
      ++rejected;
      EXPECT_NE(a.message().find("cut.obj"), std::string::npos);
    } else {
      for (const Face& f : a->topology.faces)  // an accepted prefix holds only real vertices
        for (uint32_t c : f.v) EXPECT_TRUE(c == kNoVertex || c < a->topology.vertex_count);
    }
  }
  EXPECT_GT(rejected, 10u);
}

TEST(Obj, WriteIsAtomic) {
  test::TempDir dir;
  const auto m = test::quad_grid(2, 2);
  const Status s = write_mesh(dir.file("no_such_dir/m.obj"), m.topology, m.positions);
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.message().find("no_such_dir/m.obj"), std::string::npos);
  ASSERT_TRUE(write_mesh(dir.file("m.obj"), m.topology, m.positions).ok());
  size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path())) {
    ++files;
    EXPECT_EQ(entry.path().filename(), "m.obj");  // no temporary left behind
  }
  EXPECT_EQ(files, 1u);
}

}  // namespace
}  // namespace dynpm
