// build_dpm(): the build that codes each step's positions as it reads it, instead of holding
// every step. Its file must be the in-memory build's (build_progressive_mesh + encode_dpm) byte
// for byte, on any thread count and whichever way the grid's box is found; the CLI's files must
// be those main wrote before the change; and a sequence whose later file has other faces is
// refused, naming that file and the face.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <string_view>

#include "dynpm/io.h"
#include "dynpm/pipeline.h"
#include "field_sources.h"
#include "fixtures.h"

namespace dynpm {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// The real crash box (CalculiX, 3,003 nodes, 26 steps) unpacked into `dir` as `name`.
std::string unpacked(const test::TempDir& dir, const std::string& data, const std::string& name) {
  const std::string path = dir.file(name);
  const std::string unzip = "zcat '" + test::shared_data() + "/" + data + "' > " + path;
  return std::system(unzip.c_str()) == 0 ? path : "";
}

// The real crash box, opened as the CLI opens it (an error when it cannot be unpacked).
Result<AnimationStream> open_crashbox(const test::TempDir& dir) {
  const std::string frd = unpacked(dir, "crashbox-s/crashbox-s.frd.gz", "crashbox-s.frd");
  if (frd.empty()) return Status::error("cannot unpack crashbox-s.frd.gz");
  return open_input(std::vector<std::string>{frd});
}

// The in-memory build's file and the streamed one, with `threads` for both.
void expect_same_bytes(const Topology& topology, const FrameSource& frames, BuildOptions options,
                       unsigned threads) {
  options.simplify.threads = threads;
  auto in_memory = build_progressive_mesh(topology, frames, options);
  ASSERT_TRUE(in_memory.ok()) << in_memory.message();
  const std::string expected = encode_dpm(*in_memory, 1).value();
  auto streamed = build_dpm(topology, frames, options);
  ASSERT_TRUE(streamed.ok()) << streamed.message();
  EXPECT_TRUE(streamed->bytes == expected) << threads << " threads";
  EXPECT_TRUE(streamed->mesh.positions.empty());
  EXPECT_EQ(streamed->mesh.split_count(), in_memory->split_count());
  EXPECT_EQ(streamed->mesh.quant_step, in_memory->quant_step);
}

// Handed the input (as 'dynpm build' hands it), build_dpm() writes the same file and frees the
// input's faces and their ids before coding; the vertex count and node ids stay, which the frames
// may use.
TEST(BuildDpm, HandedTheInputItWritesTheSameFileAndFreesTheFaces) {
  test::TempDir dir;
  auto stream = open_crashbox(dir);
  ASSERT_TRUE(stream.ok()) << stream.message();
  BuildOptions options;
  options.simplify.key_steps = {0, 12, 25};
  auto kept = build_dpm(stream->topology, *stream->frames, options);
  ASSERT_TRUE(kept.ok()) << kept.message();
  const Topology before = stream->topology;
  ASSERT_FALSE(before.faces.empty());
  auto handed = build_dpm(std::move(stream->topology), *stream->frames, options);
  ASSERT_TRUE(handed.ok()) << handed.message();
  EXPECT_TRUE(handed->bytes == kept->bytes);
  const Topology& after = stream->topology;
  EXPECT_TRUE(after.faces.empty() && after.part_ids.empty() && after.element_ids.empty());
  EXPECT_EQ(after.faces.capacity(), 0u);
  EXPECT_EQ(after.vertex_count, before.vertex_count);
  EXPECT_EQ(after.node_ids, before.node_ids);
  EXPECT_EQ(after.part_names, before.part_names);
}

TEST(BuildDpm, TheStreamedFileIsTheInMemoryBuildsOnAnyThreadCount) {
  test::TempDir dir;
  auto stream = open_crashbox(dir);
  ASSERT_TRUE(stream.ok()) << stream.message();
  const FrameSource& frames = *stream->frames;
  // auto:3 with the box of choose_key_steps()' pass, every step (the simplifier's box), a list
  // (a pass of its own for the box), paper lossless.
  for (const char* rule_text : {"auto:3", "all", "0,5,20", "paper"}) {
    SCOPED_TRACE(rule_text);
    const KeyStepRule rule = parse_key_step_rule(rule_text).value();
    auto choice = choose_key_steps(frames, rule);
    ASSERT_TRUE(choice.ok()) << choice.message();
    const bool read_every_step =
        rule.kind == KeyStepRule::Kind::kAuto || rule.kind == KeyStepRule::Kind::kPaper;
    EXPECT_EQ(choice->all_steps_box.has_value(), read_every_step);
    BuildOptions options;
    options.simplify.key_steps = choice->steps;
    options.all_steps_box = choice->all_steps_box;
    options.lossless = rule.kind == KeyStepRule::Kind::kPaper;
    for (unsigned threads : {1u, 2u, 3u})
      expect_same_bytes(stream->topology, frames, options, threads);
  }
}

// The crash box's steps with one coordinate of one step made NaN (the last pass, which checks
// each step on every thread, is the first to read that step when the key steps and the box are
// given).
class OneNaN final : public FrameSource {
 public:
  OneNaN(const FrameSource& inner, size_t step, size_t vertex)
      : inner_(inner), step_(step), vertex_(vertex) {}
  uint32_t vertex_count() const override { return inner_.vertex_count(); }
  size_t step_count() const override { return inner_.step_count(); }
  double step_time(size_t t) const override { return inner_.step_time(t); }
  Status read_step(size_t t, std::span<float> out) const override {
    DYNPM_RETURN_IF_ERROR(inner_.read_step(t, out));
    if (t == step_) out[vertex_ * 3 + 1] = std::numeric_limits<float>::quiet_NaN();
    return {};
  }

 private:
  const FrameSource& inner_;
  size_t step_, vertex_;
};

TEST(BuildDpm, ANonFiniteCoordinateInTheLastPassIsAnErrorNamingItsStep) {
  test::TempDir dir;
  auto stream = open_crashbox(dir);
  ASSERT_TRUE(stream.ok()) << stream.message();
  auto choice = choose_key_steps(*stream->frames, parse_key_step_rule("auto:3").value());
  ASSERT_TRUE(choice.ok()) << choice.message();
  ASSERT_EQ(choice->steps, (std::vector<size_t>{0, 12, 25}));
  BuildOptions options;
  options.simplify.key_steps = choice->steps;
  options.all_steps_box = choice->all_steps_box;
  // The last vertex (the last of the threads' ranges) and one in the middle.
  for (const size_t vertex : {size_t{3002}, size_t{1500}})
    for (const unsigned threads : {1u, 2u}) {
      options.simplify.threads = threads;
      const OneNaN frames(*stream->frames, 7, vertex);
      auto built = build_dpm(stream->topology, frames, options);
      ASSERT_FALSE(built.ok()) << threads << " threads";
      EXPECT_EQ(built.message(), "time step 7 has a non-finite coordinate");
    }
}

TEST(BuildDpm, FieldsAndLosslessStreamToTheSameBytes) {
  auto paths = expand_inputs(std::vector<std::string>{test::sample_dir() + "/frame_00*.obj"});
  ASSERT_TRUE(paths.ok()) << paths.message();
  auto a = read_animation(*paths);
  ASSERT_TRUE(a.ok()) << a.message();
  test::WithFields source(a->frames, a->topology);
  source.add_node_field("PEEQ", [](const float* p, size_t t) {
    return std::max(0.0f, std::sin(0.05f * p[0]) * float(t) * 0.1f);
  });
  source.add_element_mean("S_MISES_elem", 0);
  for (bool lossless : {false, true}) {
    BuildOptions options;
    options.lossless = lossless;
    options.simplify.key_steps = {0, a->step_count() - 1};
    expect_same_bytes(a->topology, source, options, 2);
  }
}

// FNV-1a, 64 bits: a file's fingerprint.
uint64_t fingerprint(const std::string& bytes) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ull;
  return h;
}

// The files of main's `dynpm build` before the build streamed its steps (2026-12-02, commit
// 1986465): the same bytes now (without the thumbnail, which only adds a chunk before END:
// pipeline_thumbnail_test.cpp). Remade for .dpm version 4 (the wings coded against the moved
// faces' frontier): the same splits and position sections, smaller split records. Remade for
// version 5 (the splits reordered within error bands, parents coded as steps): the same mesh
// and positions, other numbering, smaller records. Remade for version 6 (later steps guessed by
// the ring fit): the same mesh and records, smaller positions (−11 to −14 %). Remade for
// version 7 (split field values range-coded): the same bytes but the version's, the fields' FLDS
// smaller.
TEST(BuildDpm, TheCrashBoxFilesAreTheOnesBuiltBefore) {
  test::TempDir dir;
  struct Case {
    std::string input, flags;
    uint64_t fnv;
    size_t size;
  };
  const std::vector<Case> cases = {
      {unpacked(dir, "crashbox-s/crashbox-s.frd.gz", "s.frd"), "--key-steps auto:3",
       0xe85c18bf5d9267eaull, 101045},
      {dir.file("s.frd"), "--key-steps all", 0x4f5b93596033db8dull, 100744},
      {unpacked(dir, "crashbox-fields/crashbox-fields.frd.gz", "fields.frd"), "--key-steps auto:3",
       0x214264390fb9b285ull, 266179},
      {"'" + test::shared_data() + "/crashbox-mixed-5k/obj/frame_*.obj'", "--key-steps auto:3",
       0x22539f14a71020bcull, 206951}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.input + " " + c.flags);
    const std::string out = dir.file("m.dpm");
    const std::string command = std::string(DYNPM_CLI) + " build " + c.input + " " + c.flags +
                                " --no-thumbnail --quiet -o " + out + " > /dev/null";
    ASSERT_EQ(std::system(command.c_str()), 0);
    const std::string bytes = slurp(out);
    EXPECT_EQ(bytes.size(), c.size);
    EXPECT_EQ(fingerprint(bytes), c.fnv);
  }
}

// A later OBJ file of a sequence with one face rewired: the build stops before writing, naming
// that file, its line and the face.
// 'dynpm build' checks the mesh when it reads it and hands the proof down
// (SimplifyOptions::checked): the build then skips its own check and writes the same bytes.
// Without a proof, or with the proof of other faces, build_dpm() refuses a broken mesh itself.
TEST(BuildDpm, AProvenMeshIsCheckedOnceAndABrokenOneIsStillRefused) {
  test::TempDir dir;
  auto stream = open_crashbox(dir);
  ASSERT_TRUE(stream.ok()) << stream.message();
  BuildOptions options;
  options.simplify.key_steps = {0, 12, 25};
  size_t checks = 0;
  options.progress = [&checks](std::string_view phase, size_t done, size_t) {
    if (phase == "checking the mesh" && done == 0) ++checks;
  };
  auto unproven = build_dpm(stream->topology, *stream->frames, options);
  ASSERT_TRUE(unproven.ok()) << unproven.message();
  EXPECT_EQ(checks, 1u);
  ASSERT_TRUE(check_topology(stream->topology, options.simplify.checked).ok());
  auto proven = build_dpm(stream->topology, *stream->frames, options);
  ASSERT_TRUE(proven.ok()) << proven.message();
  EXPECT_EQ(checks, 1u);
  EXPECT_TRUE(proven->bytes == unproven->bytes);

  Topology broken = stream->topology;  // face 7 repeats a corner
  broken.faces[7].v[1] = broken.faces[7].v[0];
  for (const bool with_the_good_proof : {false, true}) {
    BuildOptions o = options;
    if (!with_the_good_proof) o.simplify.checked.reset();
    auto refused = build_dpm(broken, *stream->frames, o);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.message().rfind("invalid input mesh: face 7 (", 0), 0u) << refused.message();
    EXPECT_NE(refused.message().find("appears twice"), std::string::npos) << refused.message();
  }
  EXPECT_EQ(checks, 3u);
}

TEST(BuildDpm, ASequenceWhoseLaterFileHasOtherFacesIsRefusedNamingIt) {
  test::TempDir dir;
  const std::string from = test::shared_data() + "/crashbox-s/obj";
  for (const auto& entry : std::filesystem::directory_iterator(from))
    std::filesystem::copy_file(entry.path(), dir.path() / entry.path().filename());
  const std::string changed = dir.file("frame_012.obj");
  std::string text = slurp(changed);
  const size_t face = text.find("\nf ");
  ASSERT_NE(face, std::string::npos);
  const size_t first = face + 3, end = text.find(' ', first);
  const std::string corner = text.substr(first, end - first);
  text.replace(first, end - first, corner == "1" ? "2" : "1");  // the first face's first corner
  std::ofstream(changed, std::ios::binary) << text;
  const std::string out = dir.file("m.dpm"), err = dir.file("err.txt");
  const std::string command = std::string(DYNPM_CLI) + " build '" + dir.file("frame_*.obj") +
                              "' --key-steps auto:3 -o " + out + " > /dev/null 2> " + err;
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  const std::string message = slurp(err);
  EXPECT_NE(message.find(changed + ":"), std::string::npos) << message;
  EXPECT_NE(message.find(": face 0 is ("), std::string::npos) << message;
  EXPECT_NE(message.find("every time step must have the same faces"), std::string::npos) << message;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace dynpm
