// Animations as sequences of per-step files: real CalculiX results, mismatches, streaming.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "dynpm/io.h"
#include "fixtures.h"

namespace dynpm {
namespace {

std::vector<std::string> glob(const std::string& pattern) {
  auto paths = expand_inputs(std::vector<std::string>{pattern});
  EXPECT_TRUE(paths.ok()) << paths.message();
  return paths.ok() ? *paths : std::vector<std::string>{};
}

// Writes a quad grid as steps frame_000.obj … with z = t · x (a shearing animation).
std::vector<std::string> write_grid_frames(const test::TempDir& dir, size_t steps) {
  auto m = test::quad_grid(3, 2);
  std::vector<std::string> paths;
  for (size_t t = 0; t < steps; ++t) {
    std::vector<float> xyz = m.positions;
    for (size_t v = 0; v < xyz.size(); v += 3) xyz[v + 2] = float(t) * xyz[v];
    paths.push_back(*step_path(dir.file("frame_{:03d}.obj"), t));
    WriteOptions options;
    options.comment = "time " + std::to_string(0.5 * double(t));
    EXPECT_TRUE(write_mesh(paths.back(), m.topology, xyz, options).ok());
  }
  return paths;
}

struct SharedAnimation {
  const char* folder;
  uint32_t vertices;
  size_t quads, triangles, steps;
};

class SharedCrashBox : public ::testing::TestWithParam<SharedAnimation> {};

TEST_P(SharedCrashBox, ReadsWithTheRightCounts) {
  const SharedAnimation& expected = GetParam();
  const std::string folder = test::shared_data() + "/" + expected.folder + "/obj";
  if (!std::filesystem::exists(folder)) GTEST_SKIP() << "../shared/data is not beside the project";
  auto a = read_animation(glob(folder + "/frame_*.obj"));
  ASSERT_TRUE(a.ok()) << a.message();
  EXPECT_EQ(a->topology.vertex_count, expected.vertices);
  EXPECT_EQ(a->topology.quad_count(), expected.quads);
  EXPECT_EQ(a->topology.triangle_count(), expected.triangles);
  EXPECT_EQ(a->step_count(), expected.steps);
  EXPECT_TRUE(validate(*a).ok());
  // The tube is crushed: the top moves down over time, the bottom stays.
  BoundingBox first, last;
  first.extend(a->frames.step(0));
  last.extend(a->frames.step(a->step_count() - 1));
  EXPECT_LT(last.max[2], first.max[2] - 20.f);
  EXPECT_EQ(last.min[2], first.min[2]);
  EXPECT_GT(a->frames.step_time(a->step_count() - 1), a->frames.step_time(1));
}

INSTANTIATE_TEST_SUITE_P(CalculiX, SharedCrashBox,
                         ::testing::Values(SharedAnimation{"crashbox-s", 3003, 2937, 0, 26},
                                           SharedAnimation{"crashbox-mixed-5k", 4929, 4827, 16,
                                                           41}),
                         [](const ::testing::TestParamInfo<SharedAnimation>& param) {
                           std::string name = param.param.folder;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST(Sequence, ReadsTheShippedCalculixSample) {
  // data/hat-rail: gmsh + CalculiX, made by scripts/sample/make_sample.sh.
  auto a = read_animation(glob(test::sample_dir() + "/frame_*.obj"));
  ASSERT_TRUE(a.ok()) << a.message();
  EXPECT_EQ(a->topology.vertex_count, 2608u);
  EXPECT_EQ(a->topology.quad_count(), 2435u);
  EXPECT_EQ(a->topology.triangle_count(), 123u);
  EXPECT_EQ(a->step_count(), 31u);
  const ValidationReport report = validate(*a);
  EXPECT_TRUE(report.ok());
  EXPECT_EQ(report.count(Severity::kWarning), 0u);
  // The free end is pushed 120 mm in +y: the largest displacement in the last step.
  double max_displacement = 0;
  for (uint32_t v = 0; v < a->topology.vertex_count; ++v) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double d = a->frames.step(30)[v * 3 + k] - a->frames.step(0)[v * 3 + k];
      d2 += d * d;
    }
    max_displacement = std::max(max_displacement, std::sqrt(d2));
  }
  EXPECT_NEAR(max_displacement, 124.5945, 0.01);  // times.csv of the sample
}

TEST(Sequence, StepTimesComeFromTheFiles) {
  test::TempDir dir;
  auto paths = write_grid_frames(dir, 4);
  auto a = read_animation(paths);
  ASSERT_TRUE(a.ok()) << a.message();
  EXPECT_DOUBLE_EQ(a->frames.step_time(3), 1.5);
  EXPECT_FLOAT_EQ(a->frames.step(3)[3 * 3 + 2], 3.f * 3.f);  // vertex 3 is at x = 3
}

TEST(Sequence, MismatchedFacesAreRejectedWithFileAndLine) {
  test::TempDir dir;
  auto paths = write_grid_frames(dir, 3);
  // Rewire one face of frame_002.obj.
  std::ifstream in(paths[2]);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const size_t at = text.find("\nf ") + 1;
  const size_t eol = text.find('\n', at);
  text.replace(at, eol - at, "f 1 2 6 7");
  std::ofstream(paths[2]) << text;
  const size_t line = size_t(std::count(text.begin(), text.begin() + at, '\n')) + 1;

  auto a = read_animation(paths);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.message().find("frame_002.obj:" + std::to_string(line) + ": face 0"),
            std::string::npos)
      << a.message();
  EXPECT_NE(a.message().find("same faces"), std::string::npos) << a.message();
}

TEST(Sequence, MismatchedVertexCountIsRejected) {
  test::TempDir dir;
  auto paths = write_grid_frames(dir, 2);
  std::ofstream(paths[1], std::ios::app) << "v 9 9 9\n";
  auto a = read_animation(paths);
  ASSERT_FALSE(a.ok());
  EXPECT_NE(a.message().find("frame_001.obj: 13 vertices, but"), std::string::npos) << a.message();
}

TEST(Sequence, StepsAreStreamedFromDiskWhenAskedFor) {
  test::TempDir dir;
  auto paths = write_grid_frames(dir, 3);
  auto stream = open_animation(paths);
  ASSERT_TRUE(stream.ok()) << stream.message();
  std::filesystem::remove(paths[2]);  // not read yet: opening did not need it
  std::vector<float> xyz(size_t{stream->frames->vertex_count()} * 3);
  EXPECT_TRUE(stream->frames->read_step(1, xyz).ok());
  EXPECT_FLOAT_EQ(xyz[3 * 3 + 2], 3.f);
  const Status missing = stream->frames->read_step(2, xyz);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("frame_002.obj: cannot open"), std::string::npos);
}

TEST(Sequence, GlobsSortNaturallyAndFailClearly) {
  test::TempDir dir;
  for (const char* name : {"frame_10.obj", "frame_2.obj", "frame_1.obj"})
    std::ofstream(dir.file(name)) << "v 0 0 0\n";
  auto paths = expand_inputs(std::vector<std::string>{dir.file("frame_*.obj")});
  ASSERT_TRUE(paths.ok());
  ASSERT_EQ(paths->size(), 3u);
  EXPECT_EQ(std::filesystem::path((*paths)[0]).filename(), "frame_1.obj");
  EXPECT_EQ(std::filesystem::path((*paths)[1]).filename(), "frame_2.obj");
  EXPECT_EQ(std::filesystem::path((*paths)[2]).filename(), "frame_10.obj");

  auto none = expand_inputs(std::vector<std::string>{dir.file("step_*.obj")});
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.message().find("no file matches"), std::string::npos);
  auto folder = expand_inputs(std::vector<std::string>{dir.path().string()});
  ASSERT_FALSE(folder.ok());
  EXPECT_NE(folder.message().find("is a directory"), std::string::npos);
}

TEST(Sequence, NaturalOrder) {
  EXPECT_TRUE(natural_less("frame_9.obj", "frame_10.obj"));
  EXPECT_FALSE(natural_less("frame_10.obj", "frame_9.obj"));
  EXPECT_TRUE(natural_less("frame_009.obj", "frame_010.obj"));
  EXPECT_TRUE(natural_less("a2b3", "a2b10"));
  EXPECT_TRUE(natural_less("a", "b"));
  EXPECT_FALSE(natural_less("same", "same"));
}

TEST(Sequence, StepPathPatterns) {
  EXPECT_EQ(*step_path("out/f_{:03d}.ply", 7), "out/f_007.ply");
  EXPECT_EQ(*step_path("f{}.obj", 12), "f12.obj");
  EXPECT_EQ(*step_path("f{:d}.obj", 12), "f12.obj");
  EXPECT_EQ(*step_path("f{:02d}.obj", 123), "f123.obj");
  EXPECT_FALSE(step_path("plain.obj", 1).ok());
  EXPECT_FALSE(step_path("f{:x}.obj", 1).ok());
  EXPECT_FALSE(step_path("f{}{}.obj", 1).ok());
}

}  // namespace
}  // namespace dynpm
