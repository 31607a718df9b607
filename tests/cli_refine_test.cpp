// dynpm extract --refine on the CalculiX crash box with plastic strain (lossless build): the
// file holds the selective navigator's mesh in the agreed order (docs/selective.md "Output"),
// the region's vertices and faces exactly as the full mesh has them, several --refine are a
// union, and bad requests fail with the argument named and nothing written.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "crashbox_models.h"
#include "dynpm/io.h"
#include "dynpm/lod.h"
#include "random_meshes.h"
#include "third_party.h"

namespace dynpm {
namespace {

test::CommandResult dynpm_cli(const std::string& arguments) {
  return test::run_command(std::string(DYNPM_CLI) + " " + arguments);
}

using Point = std::array<float, 3>;
Point point(std::span<const float> xyz, uint32_t v) {
  return {xyz[size_t{v} * 3], xyz[size_t{v} * 3 + 1], xyz[size_t{v} * 3 + 2]};
}

// The faces of a mesh as sets of corner positions (meshes numbered differently compare).
std::multiset<std::vector<Point>> faces_by_position(const Topology& t, std::span<const float> xyz) {
  std::multiset<std::vector<Point>> out;
  for (const Face& f : t.faces) {
    std::vector<Point> corners;
    for (int c = 0; c < f.degree(); ++c) corners.push_back(point(xyz, f.v[c]));
    std::rotate(corners.begin(), std::min_element(corners.begin(), corners.end()), corners.end());
    out.insert(corners);
  }
  return out;
}

constexpr size_t kStep = 14;
const char* const kBox = "box:-40,-40,100,40,40,160";

TEST(CliRefine, WritesTheSelectiveMeshInTheAgreedOrder) {
  DYNPM_CRASHBOX_OR_SKIP(model, "crashbox-fields");
  test::TempDir dir;
  const std::string out = dir.file("refined.obj");
  auto r = dynpm_cli("extract " + model->dpm + " --step " + std::to_string(kStep) + " --refine " +
                     kBox + " --elsewhere 5% -o " + out);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto written = read_mesh(out);
  ASSERT_TRUE(written.ok()) << written.message();
  const auto xyz = written->frames.step(0);

  // The library's navigator on the same request: vertices and faces in the same order.
  const ProgressiveMesh& m = model->mesh;
  const SplitDependencies deps = derive_split_dependencies(m);
  const RefineTargets targets(m, deps);
  const RefineTarget box = parse_refine_target(kBox).value();
  const ElsewhereLevel five = parse_elsewhere("5%").value();
  SelectiveNavigator nav(m, deps);
  nav.set_active(targets.request(five, std::span(&box, 1), kStep).value());
  const SelectiveMesh want = nav.active_mesh();
  ASSERT_EQ(written->topology.vertex_count, want.vertices.size());
  ASSERT_EQ(written->topology.faces, want.topology.faces);
  for (size_t k = 0; k < want.vertices.size(); ++k)
    ASSERT_EQ(point(xyz, uint32_t(k)), point(m.positions[kStep], want.vertices[k])) << k;
  test::expect_clean(written->topology, "refined");

  // Against the full mesh: every vertex in the box there, at its position, and every face of the
  // full mesh whose corners all lie in the box, with those corners.
  const std::string full = dir.file("full.obj");
  ASSERT_EQ(
      dynpm_cli("extract " + model->dpm + " --full --step " + std::to_string(kStep) + " -o " + full)
          .exit_code,
      0);
  auto original = read_mesh(full);
  ASSERT_TRUE(original.ok()) << original.message();
  const auto full_xyz = original->frames.step(0);
  std::set<Point> present;
  for (uint32_t v = 0; v < written->topology.vertex_count; ++v) present.insert(point(xyz, v));
  auto inside = [&](const Point& p) {
    return p[0] >= -40 && p[0] <= 40 && p[1] >= -40 && p[1] <= 40 && p[2] >= 100 && p[2] <= 160;
  };
  size_t in_box = 0;
  for (uint32_t v = 0; v < original->topology.vertex_count; ++v)
    if (inside(point(full_xyz, v))) {
      ++in_box;
      ASSERT_TRUE(present.count(point(full_xyz, v))) << "vertex " << v;
    }
  EXPECT_GT(in_box, 500u);
  EXPECT_LT(written->topology.vertex_count, original->topology.vertex_count);
  const auto refined_faces = faces_by_position(written->topology, xyz);
  Topology box_faces;
  for (const Face& f : original->topology.faces) {
    bool all = true;
    for (int c = 0; c < f.degree(); ++c) all = all && inside(point(full_xyz, f.v[c]));
    if (all) box_faces.faces.push_back(f);
  }
  EXPECT_GT(box_faces.faces.size(), 400u);
  for (const auto& f : faces_by_position(box_faces, full_xyz))
    ASSERT_TRUE(refined_faces.count(f)) << "a face of the box is missing";
}

TEST(CliRefine, SeveralRequestsAreAUnion) {
  DYNPM_CRASHBOX_OR_SKIP(model, "crashbox-fields");
  test::TempDir dir;
  auto vertices = [&](const std::string& refine) {
    auto r = dynpm_cli("extract " + model->dpm + " --step 10 " + refine +
                       " --elsewhere 300 --json -o " + dir.file("u.vtk"));
    EXPECT_EQ(r.exit_code, 0) << r.output;
    const size_t at = r.output.find("\"vertices\": ");
    return at == std::string::npos ? 0 : std::stoul(r.output.substr(at + 12));
  };
  const size_t box = vertices(std::string("--refine ") + kBox);
  const size_t peeq = vertices("--refine 'field:PEEQ>0.05'");
  const size_t moved = vertices("--refine 'moved:>20'");
  const size_t all = vertices(std::string("--refine ") + kBox +
                              " --refine 'field:PEEQ>0.05' --refine 'moved:>20'");
  EXPECT_GT(box, 300u);
  EXPECT_GT(peeq, 300u);
  EXPECT_GT(moved, 300u);
  EXPECT_GE(all, std::max({box, peeq, moved}));
  EXPECT_LE(all, box + peeq + moved);
  EXPECT_EQ(vertices("--refine part:1"), model->mesh.full_vertex_count);
}

// "--step last" is the model's last step (14 of crashbox-fields' 15): the regions are taken there.
TEST(CliRefine, StepLastIsTheLastStep) {
  DYNPM_CRASHBOX_OR_SKIP(model, "crashbox-fields");
  test::TempDir dir;
  for (const char* step : {"14", "last"}) {
    auto r = dynpm_cli("extract " + model->dpm + " --step " + step +
                       " --refine 'moved:>20' --elsewhere 5% -o " +
                       dir.file(step + std::string(".vtk")));
    ASSERT_EQ(r.exit_code, 0) << step << "\n" << r.output;
  }
  EXPECT_EQ(test::run_command("cmp " + dir.file("14.vtk") + " " + dir.file("last.vtk")).exit_code,
            0);
}

TEST(CliRefine, BadRequestsNameTheArgumentAndWriteNothing) {
  DYNPM_CRASHBOX_OR_SKIP(model, "crashbox-fields");
  test::TempDir dir;
  const std::string out = dir.file("bad.obj");
  const std::pair<std::string, std::string> cases[] = {
      {"--step 3 --refine box:1,2,3 --elsewhere 5%", "--refine 'box:1,2,3': a box is"},
      {"--step 3 --refine box:2,0,0,1,1,1 --elsewhere 5%", "first corner must be its smallest"},
      {"--step 3 --refine cube:1 --elsewhere 5%", "unknown kind 'cube'"},
      {"--step 3 --refine 'field:PEEQ>x' --elsewhere 5%", "is not a number"},
      {"--step 3 --refine 'field:FOO>1' --elsewhere 5%", "no field 'FOO' (it has S_MISES, PEEQ"},
      {"--step 3 --refine part:9 --elsewhere 5%", "--refine part:9: the model has no part 9"},
      {"--step 3 --refine moved:5 --elsewhere 5%", "moved:>D"},
      {"--step 3 --refine sphere:0,0,0,-1 --elsewhere 5%", "radius cannot be negative"},
      {"--step 3 --refine 'view:EYE=0,0,0;AT=0,0,1;FOV=45;H=700' --elsewhere 5%", "no PX"},
      {"--step 3 --refine 'view:EYE=0,0,0;AT=0,0,1;FOV=45;H=700;PX=1' --elsewhere 5%",
       "UP is along the view direction"},
      {"--step 3 --refine 'view:EYE=0,0,0;AT=1,0,0;FOV=190;H=700;PX=1' --elsewhere 5%",
       "FOV is in degrees"},
      {"--step 3 --refine 'view:EYE=0,0;AT=1,0,0;FOV=45;H=700;PX=1' --elsewhere 5%",
       "EYE needs 3 numbers"},
      {"--step 3 --refine 'view:EYE=0,0,0;AT=1,0,0;FOV=45;H=700;PX=1;ZOOM=2' --elsewhere 5%",
       "unknown key 'ZOOM'"},
      {"--step 3 --refine box:0,0,0,1,1,1 --elsewhere 500%", "--elsewhere '500%'"},
      {"--step 3 --refine box:0,0,0,1,1,1 --elsewhere error:x", "--elsewhere 'error:x'"},
      {"--step 3 --refine box:0,0,0,1,1,1 --elsewhere 2.5", "--elsewhere '2.5'"},
      {"--step 3 --refine box:0,0,0,1,1,1", "--refine needs --elsewhere"},
      {"--step 3 --elsewhere 5%", "--elsewhere needs at least one --refine"},
      {"--step 3 --refine box:0,0,0,1,1,1 --elsewhere 5% --ratio 0.1", "--ratio cannot go with"},
      {"--refine box:0,0,0,1,1,1 --elsewhere 5%", "--refine needs --step"},
      {"--step 99 --refine box:0,0,0,1,1,1 --elsewhere 5%", "--step needs a number in [0, 14]"},
  };
  for (const auto& [arguments, message] : cases) {
    auto r = dynpm_cli("extract " + model->dpm + " " + arguments + " -o " + out);
    EXPECT_EQ(r.exit_code, 2) << arguments << "\n" << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << arguments << "\n" << r.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << arguments;
  }
  // A prefix of the file holds too few splits for full resolution anywhere.
  const std::string prefix = dir.file("prefix.dpm");
  std::filesystem::copy_file(model->dpm, prefix);
  std::filesystem::resize_file(prefix, std::filesystem::file_size(prefix) / 4);
  auto r = dynpm_cli("extract " + prefix + " --step 1 --refine box:0,0,0,1,1,1 --elsewhere 5% -o " +
                     out);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("is a prefix of a file"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--refine needs the whole file"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace dynpm
