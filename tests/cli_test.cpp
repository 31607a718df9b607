// The dynpm command as a user runs it: exit codes, messages, and files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "dynpm/io.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

test::CommandResult dynpm_cli(const std::string& arguments) {
  return test::run_command(std::string(DYNPM_CLI) + " " + arguments);
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::string crashbox_glob() { return test::shared_data() + "/crashbox-s/obj/frame_*.obj"; }

TEST(Cli, InfoOnTheCalculixCrashBox) {
  if (!std::filesystem::exists(test::shared_data())) GTEST_SKIP() << "no ../shared/data";
  auto r = dynpm_cli("info '" + crashbox_glob() + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "vertices      3003")) << r.output;
  EXPECT_TRUE(contains(r.output, "2937 faces") ||
              contains(r.output, "2937 (2937 quads, 0 triangles)"))
      << r.output;
  EXPECT_TRUE(contains(r.output, "time steps    26")) << r.output;
  EXPECT_TRUE(contains(r.output, "validation    ok")) << r.output;

  auto json = dynpm_cli("info --json '" + crashbox_glob() + "'");
  ASSERT_EQ(json.exit_code, 0) << json.output;
  for (const char* field : {"\"vertices\": 3003", "\"quads\": 2937", "\"triangles\": 0",
                            "\"steps\": 26", "\"ok\": true"})
    EXPECT_TRUE(contains(json.output, field)) << field << "\n" << json.output;
}

TEST(Cli, InfoReportsValidationErrorsWithExitCode3) {
  test::TempDir dir;
  const auto m = test::valence_two_quads();
  ASSERT_TRUE(write_mesh(dir.file("m2.obj"), m.topology, m.positions).ok());
  auto r = dynpm_cli("info " + dir.file("m2.obj"));
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_TRUE(contains(r.output, "INVALID")) << r.output;
  EXPECT_TRUE(contains(r.output, "(M2)")) << r.output;
}

TEST(Cli, BadInputIsAClearErrorAndNonZeroExit) {
  test::TempDir dir;
  std::ofstream(dir.file("bad.obj")) << "v 0 0 0\nv 1 0 0\nf 1 2 7\n";
  auto r = dynpm_cli("info " + dir.file("bad.obj"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.output, dir.file("bad.obj") + ":3: face index 7")) << r.output;

  auto missing = dynpm_cli("info " + dir.file("missing.obj"));
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_TRUE(contains(missing.output, "no such file")) << missing.output;

  auto usage = dynpm_cli("info --bogus x.obj");
  EXPECT_EQ(usage.exit_code, 2);
  EXPECT_TRUE(contains(usage.output, "unknown option '--bogus'")) << usage.output;
}

TEST(Cli, EveryVerbHasHelp) {
  for (const char* verb : {"info", "convert"}) {
    auto r = dynpm_cli(std::string(verb) + " --help");
    EXPECT_EQ(r.exit_code, 0) << verb;
    EXPECT_TRUE(contains(r.output, std::string("usage: dynpm ") + verb)) << r.output;
  }
  auto top = dynpm_cli("--help");
  EXPECT_EQ(top.exit_code, 0);
  EXPECT_TRUE(contains(top.output, "convert"));
}

TEST(Cli, ConvertAnAnimationToPlyAndBackKeepsEverything) {
  if (!std::filesystem::exists(test::shared_data())) GTEST_SKIP() << "no ../shared/data";
  test::TempDir dir;
  auto r = dynpm_cli("convert '" + crashbox_glob() + "' -o " + dir.file("step_{:02d}.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "wrote 26 steps")) << r.output;
  auto original = read_animation(*expand_inputs(std::vector<std::string>{crashbox_glob()}));
  auto converted = read_animation(*expand_inputs(std::vector<std::string>{dir.file("step_*.ply")}));
  ASSERT_TRUE(original.ok() && converted.ok()) << converted.message();
  EXPECT_EQ(converted->topology.faces, original->topology.faces);
  ASSERT_EQ(converted->step_count(), 26u);
  for (size_t t = 0; t < 26; ++t) {
    auto a = original->frames.step(t), b = converted->frames.step(t);
    EXPECT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << "step " << t;
    EXPECT_DOUBLE_EQ(converted->frames.step_time(t), original->frames.step_time(t));
  }
}

TEST(Cli, ConvertNeedsAStepPatternForSeveralSteps) {
  if (!std::filesystem::exists(test::shared_data())) GTEST_SKIP() << "no ../shared/data";
  test::TempDir dir;
  auto r = dynpm_cli("convert '" + crashbox_glob() + "' -o " + dir.file("one.ply"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(contains(r.output, "26 time steps")) << r.output;
  EXPECT_FALSE(std::filesystem::exists(dir.file("one.ply")));
}

std::string sample_glob() { return test::sample_dir() + "/frame_*.obj"; }

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The numbers that follow `"key": ` in `text`, in order.
std::vector<double> json_numbers(const std::string& text, const std::string& key) {
  std::vector<double> values;
  const std::string needle = "\"" + key + "\": ";
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1))
    values.push_back(std::stod(text.substr(at + needle.size())));
  return values;
}

TEST(Cli, EvalMeasuresAProgressiveMeshAtSeveralResolutionsAndSteps) {
  if (!std::filesystem::exists(test::sample_dir())) GTEST_SKIP() << "no sample";
  test::TempDir dir;
  auto build = dynpm_cli("build '" + sample_glob() + "' -o " + dir.file("rail.dpm"));
  ASSERT_EQ(build.exit_code, 0) << build.output;
  auto r = dynpm_cli("eval '" + sample_glob() + "' --dpm " + dir.file("rail.dpm") +
                     " --ratios 2,10,50,100 --steps 0,30 --json " + dir.file("e.json") +
                     " --plot " + dir.file("e.svg"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "max over all 31 steps")) << r.output;
  EXPECT_TRUE(contains(r.output, "step 30")) << r.output;

  ASSERT_TRUE(std::filesystem::exists(dir.file("e.json")));
  const std::string json = read_text(dir.file("e.json"));
  // Per ratio, in order: the two chosen steps' hausdorff_pct, then the max's.
  const std::vector<double> h = json_numbers(json, "hausdorff_pct");
  const std::vector<double> ratio = json_numbers(json, "ratio_pct");
  ASSERT_EQ(ratio, (std::vector<double>{2, 10, 50, 100})) << json;
  ASSERT_EQ(h.size(), 4u * 3u) << json;
  for (size_t column = 0; column < 3; ++column) {
    for (size_t row = 1; row < 4; ++row)
      EXPECT_LE(h[row * 3 + column], h[(row - 1) * 3 + column])
          << "column " << column << ", row " << row << "\n"
          << json;
    EXPECT_LE(h[3 * 3 + column], 0.01) << "full resolution, column " << column << "\n" << json;
    EXPECT_GT(h[column], 0.01) << "2% of the vertices, column " << column << "\n" << json;
  }
  const std::vector<double> vertices = json_numbers(json, "vertices");
  ASSERT_EQ(vertices.size(), 5u) << json;  // the original's, then one per ratio
  EXPECT_EQ(vertices[4], vertices[0]) << json;
  for (const char* field :
       {"\"faces\": ", "\"level_error\": ", "\"mean_pct\": ", "\"rms_pct\": ", "\"max\": {"})
    EXPECT_TRUE(contains(json, field)) << field << "\n" << json;

  const std::string svg = read_text(dir.file("e.svg"));
  EXPECT_TRUE(svg.rfind("<svg", 0) == 0 || svg.rfind("<?xml", 0) == 0) << svg.substr(0, 100);
  EXPECT_TRUE(contains(svg, "</svg>"));
  EXPECT_TRUE(contains(svg, "<polyline"));

  // A sample of the steps for long animations: 0, 10, 20 and the last, the max over those.
  auto sampled = dynpm_cli("eval '" + sample_glob() + "' --dpm " + dir.file("rail.dpm") +
                           " --ratios 10 --steps every:10 --json " + dir.file("s.json"));
  ASSERT_EQ(sampled.exit_code, 0) << sampled.output;
  EXPECT_TRUE(contains(sampled.output, "max over these steps")) << sampled.output;
  const std::string sampled_json = read_text(dir.file("s.json"));
  std::vector<double> measured = json_numbers(sampled_json, "step");
  ASSERT_EQ(measured.size(), 4u + 1u) << sampled_json;  // the four steps, then the max's step
  measured.pop_back();
  EXPECT_EQ(measured, (std::vector<double>{0, 10, 20, 30})) << sampled_json;
  EXPECT_TRUE(contains(sampled_json, "\"max_over\": \"chosen\"")) << sampled_json;
  auto zero = dynpm_cli("eval '" + sample_glob() + "' --dpm " + dir.file("rail.dpm") +
                        " --ratios 10 --steps every:0");
  EXPECT_EQ(zero.exit_code, 2) << zero.output;
  // 'last' names the last step (30 of the sample's 31).
  auto last =
      dynpm_cli("eval '" + sample_glob() + "' --dpm " + dir.file("rail.dpm") +
                " --ratios 10 --steps 10,last --max-over chosen --json " + dir.file("l.json"));
  ASSERT_EQ(last.exit_code, 0) << last.output;
  measured = json_numbers(read_text(dir.file("l.json")), "step");
  ASSERT_EQ(measured.size(), 3u) << read_text(dir.file("l.json"));
  EXPECT_EQ(measured[0], 10);
  EXPECT_EQ(measured[1], 30);
}

TEST(Cli, EvalRefusesAModelOfAnotherMeshAndBadArguments) {
  if (!std::filesystem::exists(test::sample_dir())) GTEST_SKIP() << "no sample";
  test::TempDir dir;
  auto build = dynpm_cli("build '" + sample_glob() + "' -o " + dir.file("rail.dpm"));
  ASSERT_EQ(build.exit_code, 0) << build.output;
  const auto m = test::valence_two_quads();
  ASSERT_TRUE(write_mesh(dir.file("other.obj"), m.topology, m.positions).ok());
  auto other = dynpm_cli("eval " + dir.file("other.obj") + " --dpm " + dir.file("rail.dpm") +
                         " --ratios 10");
  EXPECT_EQ(other.exit_code, 1) << other.output;
  EXPECT_TRUE(contains(other.output, "was built from another mesh")) << other.output;

  auto missing =
      dynpm_cli("eval '" + sample_glob() + "' --dpm " + dir.file("none.dpm") + " --ratios 10");
  EXPECT_EQ(missing.exit_code, 1) << missing.output;
  EXPECT_TRUE(contains(missing.output, "none.dpm")) << missing.output;

  for (const char* ratios : {"0", "101", "5,x", "-3"}) {
    auto bad = dynpm_cli("eval '" + sample_glob() + "' --dpm " + dir.file("rail.dpm") +
                         " --ratios=" + ratios);
    EXPECT_EQ(bad.exit_code, 2) << ratios << "\n" << bad.output;
    EXPECT_TRUE(contains(bad.output, "--ratios")) << bad.output;
  }
  auto step = dynpm_cli("eval '" + sample_glob() + "' --dpm " + dir.file("rail.dpm") +
                        " --ratios 10 --steps 0,31");
  EXPECT_EQ(step.exit_code, 2) << step.output;
  EXPECT_TRUE(contains(step.output, "--steps needs step numbers in [0, 30]")) << step.output;
}

}  // namespace
}  // namespace dynpm

namespace dynpm {
namespace {

// The main job end to end: build from CalculiX's own .frd, then a lossless extraction at full
// resolution is the same animation as the OBJ sequence of that run; info describes the model
// and its result fields.
TEST(Cli, BuildFromFrdExtractFullIsTheInputAndInfoDescribesTheModel) {
  test::TempDir dir;
  const std::string frd = dir.file("rail.frd");
  ASSERT_EQ(
      std::system(("zcat '" + test::source_dir() + "/data/hat-rail/rail.frd.gz' > " + frd).c_str()),
      0);
  // The sample's stress and plastic strain, listed by info on the .frd itself.
  auto frd_info = dynpm_cli("info " + frd);
  ASSERT_EQ(frd_info.exit_code, 0) << frd_info.output;
  EXPECT_TRUE(contains(frd_info.output, "S_MISES") && contains(frd_info.output, "PEEQ"))
      << frd_info.output;
  auto build = dynpm_cli("build " + frd + " --lossless -o " + dir.file("rail.dpm"));
  ASSERT_EQ(build.exit_code, 0) << build.output;
  EXPECT_TRUE(contains(build.output, "vertex splits rebuild the input")) << build.output;
  auto extract =
      dynpm_cli("extract " + dir.file("rail.dpm") + " --full -o " + dir.file("full_{:03d}.ply"));
  ASSERT_EQ(extract.exit_code, 0) << extract.output;
  auto stream = open_input(std::vector<std::string>{frd});
  ASSERT_TRUE(stream.ok()) << stream.message();
  auto original = load_all_steps(std::move(stream).value());
  auto back = read_animation(*expand_inputs(std::vector<std::string>{dir.file("full_*.ply")}));
  ASSERT_TRUE(original.ok() && back.ok()) << back.message();
  ASSERT_EQ(back->step_count(), original->step_count());
  EXPECT_EQ(back->topology.faces, original->topology.faces);
  EXPECT_EQ(back->topology.node_ids, original->topology.node_ids);
  EXPECT_EQ(back->topology.part_ids, original->topology.part_ids);
  for (size_t t = 0; t < back->step_count(); ++t) {
    const auto a = original->frames.step(t), b = back->frames.step(t);
    ASSERT_TRUE(std::equal(a.begin(), a.end(), b.begin(), b.end())) << "step " << t;
  }
  // One step of the full mesh is in the input's order too (reading only the steps up to it
  // once made the navigator's order come out).
  auto one =
      dynpm_cli("extract " + dir.file("rail.dpm") + " --full --step 3 -o " + dir.file("full3.ply"));
  ASSERT_EQ(one.exit_code, 0) << one.output;
  auto step3 = read_mesh(dir.file("full3.ply"));
  ASSERT_TRUE(step3.ok()) << step3.message();
  EXPECT_EQ(step3->topology.faces, original->topology.faces);
  const auto a3 = original->frames.step(3), b3 = step3->frames.step(0);
  EXPECT_TRUE(std::equal(a3.begin(), a3.end(), b3.begin(), b3.end()));
  auto info = dynpm_cli("info " + dir.file("rail.dpm") + " --json");
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_TRUE(contains(info.output, "\"splits\"")) << info.output;
  EXPECT_TRUE(contains(info.output, "\"lossless\": true")) << info.output;
  auto coarse = dynpm_cli("extract " + dir.file("rail.dpm") + " --max-error 1% --step 12.5 -o " +
                          dir.file("c.obj"));
  EXPECT_EQ(coarse.exit_code, 0) << coarse.output;
  // A prefix of the file (a copy cut short) gives what it holds, and says so, with --step too.
  const std::string prefix = dir.file("prefix.dpm");
  std::filesystem::copy_file(dir.file("rail.dpm"), prefix);
  std::filesystem::resize_file(prefix, std::filesystem::file_size(prefix) / 3);
  for (const std::string step : {"", " --step 3"}) {
    auto cut = dynpm_cli("extract " + prefix + " --full" + step + " -o " +
                         dir.file(step.empty() ? "cut_{:03d}.ply" : "cut.ply"));
    EXPECT_EQ(cut.exit_code, 0) << cut.output;
    EXPECT_TRUE(contains(cut.output, "is a prefix of a file; it holds ")) << step << cut.output;
  }
  auto bad = dynpm_cli("extract " + frd + " --full -o " + dir.file("x_{:03d}.obj"));
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_TRUE(contains(bad.output, "not a .dpm file")) << bad.output;
}

// A file whose name has glob characters opens as itself when it exists (a literal path wins
// over a pattern); a pattern that names no file is still a pattern.
TEST(Cli, AnExistingFileNamedLikeAPatternOpensAsItself) {
  test::TempDir dir;
  const auto m = test::quad_grid(2, 2);
  ASSERT_TRUE(write_mesh(dir.file("run[1].obj"), m.topology, m.positions).ok());
  auto r = dynpm_cli("info '" + dir.file("run[1].obj") + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(contains(r.output, "vertices      9")) << r.output;
  auto pattern = dynpm_cli("info '" + dir.file("run[2-9].obj") + "'");
  EXPECT_EQ(pattern.exit_code, 1) << pattern.output;
  EXPECT_TRUE(contains(pattern.output, "no file matches this pattern")) << pattern.output;
}

// Reports never print "-nan%" (a model whose every vertex is at one point has diagonal 0), and a
// file larger than float32 says "larger", not "0.7x smaller".
TEST(Cli, ReportsOfAPointModelAndOfAFileLargerThanItsFloats) {
  test::TempDir dir;
  auto m = test::quad_grid(2, 2);
  ASSERT_TRUE(write_mesh(dir.file("grid.obj"), m.topology, m.positions).ok());
  auto build = dynpm_cli("build " + dir.file("grid.obj") + " -o " + dir.file("grid.dpm"));
  ASSERT_EQ(build.exit_code, 0) << build.output;
  EXPECT_TRUE(contains(build.output, "× larger than float32")) << build.output;
  EXPECT_FALSE(contains(build.output, "smaller")) << build.output;

  std::fill(m.positions.begin(), m.positions.end(), 1.0f);
  ASSERT_TRUE(write_mesh(dir.file("point.obj"), m.topology, m.positions).ok());
  auto point = dynpm_cli("build " + dir.file("point.obj") + " -o " + dir.file("point.dpm"));
  ASSERT_EQ(point.exit_code, 0) << point.output;
  auto extract = dynpm_cli("extract " + dir.file("point.dpm") + " --full --step 0 -o " +
                           dir.file("point-back.obj"));
  ASSERT_EQ(extract.exit_code, 0) << extract.output;
  auto info = dynpm_cli("info " + dir.file("point.dpm"));
  ASSERT_EQ(info.exit_code, 0) << info.output;
  for (const auto* r : {&point, &extract, &info})
    EXPECT_FALSE(contains(r->output, "nan")) << r->output;
}

// Every numeric flag has a range, checked before any work; the message names the flag, the
// range and the value. (More cases, one per verb, in tests/bad/expected.txt.)
TEST(Cli, NumericFlagsOutsideTheirRangeAreRefused) {
  test::TempDir dir;
  const auto m = test::quad_grid(2, 2);
  ASSERT_TRUE(write_mesh(dir.file("grid.obj"), m.topology, m.positions).ok());
  ASSERT_EQ(dynpm_cli("build " + dir.file("grid.obj") + " -o " + dir.file("g.dpm")).exit_code, 0);
  const std::string grid = dir.file("grid.obj"), model = dir.file("g.dpm");
  const std::string out = " -o " + dir.file("out.obj");
  const std::string huge(5000, '9');
  struct Case {
    std::string arguments, message;
  };
  for (const Case& c : std::vector<Case>{
           {"extract " + model + " --full --step nan" + out,
            "--step needs a number ≥ 0 or 'last', got 'nan'"},
           {"extract " + model + " --full --step 1e400" + out, "got '1e400'"},
           {"extract " + model + " --full --step -1" + out,
            "--step needs a number ≥ 0 or 'last', got '-1'"},
           {"extract " + model + " --full --step 3" + out,
            "--step needs a number in [0, 0] or 'last' (" + model + " has 1 step), got '3'"},
           {"extract " + model + " --full --step Last" + out, "got 'Last'"},
           {"extract " + model + " --vertices 0 --step 0" + out,
            "--vertices needs a whole number in [1, 4294967294], got '0'"},
           {"extract " + model + " --vertices 1e12 --step 0" + out, "--vertices needs a whole"},
           {"extract " + model + " --ratio 0 --step 0" + out, "--ratio needs a number in (0, 1]"},
           {"extract " + model + " --max-error nan --step 0" + out,
            "--max-error needs a number ≥ 0"},
           {"extract " + model + " --max-error 200% --step 0" + out,
            "--max-error (in %) needs a number in [0, 100], got '200'"},
           {"build " + grid + " --position-error inf -o " + model,
            "--position-error needs a number in (0, 1]"},
           {"build " + grid + " --position-error 0 -o " + model,
            "--position-error needs a number in (0, 1]"},
           {"build " + grid + " --boundary-weight nan -o " + model,
            "--boundary-weight needs a number in [0, 1000000]"},
           {"build " + grid + " --rounds 1.5 -o " + model, "--rounds needs a number in [0, 1]"},
           {"simplify " + grid + " --ratio 0.5 --rounds -0.1" + out, "--rounds needs"},
           {"simplify " + grid + " --ratio 1.5" + out,
            "--ratio needs a number in (0, 1], got '1.5'"},
           {"simplify " + grid + " --max-error nan" + out, "--max-error needs a number ≥ 0"},
           {"simplify " + grid + " --faces -3" + out, "--faces needs a whole number"},
           {"simplify " + grid + " --ratio 0.5 --boundary-weight -1" + out,
            "--boundary-weight needs"},
           {"hausdorff " + grid + " " + grid + " --samples-per-face 0",
            "--samples-per-face needs a number in (0, 10000]"},
           {"hausdorff " + grid + " " + grid + " --diagonal -1", "--diagonal needs a number > 0"},
           {"hausdorff " + grid + " " + grid + " --threads 5000",
            "--threads needs a whole number in [0, 1024]"},
           {"eval " + grid + " --dpm " + model + " --ratios 50,nan",
            "--ratios needs a number in (0, 100]"},
           {"eval " + grid + " --dpm " + model + " --ratios 50 --steps 1.5",
            "--steps needs a whole number"},
           {"eval " + grid + " --dpm " + model + " --ratios 50 --seed -1",
            "--seed needs a whole number"},
           {"info " + grid + " --problems -1", "--problems needs a whole number"},
           // A value's length in a message is bounded.
           {"extract " + model + " --full --step " + huge + out, "…' (5000 characters)"},
           {"build " + grid + " --key-steps auto:" + huge + " -o " + model,
            "key steps "
            "'auto:999999999999999999999999999999999999999999999999999999999999999999999999999… "
            "(5005 bytes)'"},
       }) {
    SCOPED_TRACE(c.arguments.substr(0, 200));
    auto r = dynpm_cli(c.arguments);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(contains(r.output, c.message)) << r.output;
    EXPECT_LT(r.output.size(), 400u) << r.output.substr(0, 400);
  }
  EXPECT_FALSE(std::filesystem::exists(dir.file("out.obj")));
}

// extract into a missing folder names the output, before the model is read.
TEST(Cli, ExtractIntoAMissingFolderNamesTheOutput) {
  test::TempDir dir;
  const auto m = test::quad_grid(2, 2);
  ASSERT_TRUE(write_mesh(dir.file("grid.obj"), m.topology, m.positions).ok());
  ASSERT_EQ(dynpm_cli("build " + dir.file("grid.obj") + " -o " + dir.file("g.dpm")).exit_code, 0);
  auto r = dynpm_cli("extract " + dir.file("g.dpm") + " --full --step 0 -o " +
                     dir.file("missing/level.obj"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(contains(r.output, "dynpm extract: " + dir.file("missing/level.obj") +
                                     ": no folder '" + dir.file("missing") + "' to write into"))
      << r.output;
  EXPECT_FALSE(contains(r.output, ".tmp-")) << r.output;
}

// info lists each field with where it lives and its range over all steps; the integration
// point of d3plot shell results is one flag, refused when it names no point.
TEST(Cli, InfoListsFieldsWithLocationAndRange) {
  const std::string qd = test::shared_data() + "/external/d3plot/qd_d3plot";
  if (!std::filesystem::exists(qd)) GTEST_SKIP() << qd << " is missing";
  auto text = dynpm_cli("info " + qd);
  ASSERT_EQ(text.exit_code, 0) << text.output;
  EXPECT_TRUE(contains(text.output, "fields        4 (")) << text.output;
  EXPECT_TRUE(contains(text.output, "  von Mises  element, ")) << text.output;
  EXPECT_TRUE(contains(text.output, "  |V|  node, ")) << text.output;
  auto json = dynpm_cli("info --json --integration-point max " + qd);
  ASSERT_EQ(json.exit_code, 0) << json.output;
  for (const char* part : {"\"name\": \"plastic strain\"", "\"location\": \"element\"",
                           "\"location\": \"node\"", "\"unit\": \"\"", "\"min\": 0", "\"max\": "})
    EXPECT_TRUE(contains(json.output, part)) << part << "\n" << json.output;
  auto bad = dynpm_cli("info --integration-point side " + qd);
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_TRUE(contains(bad.output,
                       "--integration-point: expected mid, top, bottom or max, not "
                       "'side'"))
      << bad.output;
}

}  // namespace
}  // namespace dynpm
