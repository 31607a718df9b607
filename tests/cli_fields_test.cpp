// Result fields through the command line, on the CalculiX crash box written with S and PEEQ:
// convert keeps them exactly, build stores them within their bound, and extract writes at every
// level what the level shows — with the max aggregate the original's peak, never less.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "dynpm/io.h"
#include "dynpm/progressive.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

test::CommandResult dynpm_cli(const std::string& arguments) {
  return test::run_command(std::string(DYNPM_CLI) + " " + arguments);
}

// The crash box unpacked into `dir`, or "" when the shared data is missing.
std::string crashbox_fields(const test::TempDir& dir) {
  const std::string gz = test::shared_data() + "/crashbox-fields/crashbox-fields.frd.gz";
  const std::string frd = dir.file("crashbox-fields.frd");
  if (std::system(("zcat '" + gz + "' > '" + frd + "' 2>/dev/null").c_str()) != 0) return "";
  return frd;
}

const ScalarField* field_named(const Animation& a, const std::string& name) {
  for (const ScalarField& f : a.fields)
    if (f.name == name) return &f;
  return nullptr;
}

float largest_magnitude(std::span<const float> values) {
  float best = 0;
  for (float v : values) best = std::max(best, std::abs(v));
  return best;
}

class CrashboxFields : public ::testing::Test {
 protected:
  void SetUp() override {
    frd_ = crashbox_fields(dir_);
    if (frd_.empty()) GTEST_SKIP() << "../shared/data/crashbox-fields is missing";
    auto stream = open_input(std::vector<std::string>{frd_});
    ASSERT_TRUE(stream.ok()) << stream.message();
    auto all = load_all_steps(std::move(stream).value());
    ASSERT_TRUE(all.ok()) << all.message();
    original_ = std::move(all).value();
    ASSERT_NE(field_named(original_, "PEEQ"), nullptr);
    ASSERT_NE(field_named(original_, "S_MISES"), nullptr);
  }

  test::TempDir dir_;
  std::string frd_;
  Animation original_;
};

TEST_F(CrashboxFields, ConvertKeepsEveryFieldExactly) {
  auto convert = dynpm_cli("convert " + frd_ + " -o " + dir_.file("c_{:03d}.vtu"));
  ASSERT_EQ(convert.exit_code, 0) << convert.output;
  const size_t last = original_.step_count() - 1;
  auto back = read_mesh(*step_path(dir_.file("c_{:03d}.vtu"), last));
  ASSERT_TRUE(back.ok()) << back.message();
  for (const char* name : {"PEEQ", "S_MISES"}) {
    const ScalarField* read = field_named(*back, name);
    ASSERT_NE(read, nullptr) << name;
    EXPECT_EQ(read->steps.at(0), field_named(original_, name)->steps[last]) << name;
  }
}

// At 5 % and 25 % of the vertices and at the last step, the largest value extract writes is the
// original's largest at that step (within the stored bound) with the max aggregate, and no larger
// with the mean; fully refined, every value is the original's within the bound.
TEST_F(CrashboxFields, ExtractShowsThePeakAtEveryLevel) {
  const std::string dpm = dir_.file("box.dpm");
  auto build = dynpm_cli("build " + frd_ + " -o " + dpm);
  ASSERT_EQ(build.exit_code, 0) << build.output;
  auto model = read_dpm(dpm);
  ASSERT_TRUE(model.ok()) << model.message();
  ASSERT_GE(model->fields.size(), 2u);  // S_MISES, PEEQ (and ccx's ERROR estimate)
  const size_t last = original_.step_count() - 1;
  for (const ProgressiveField& f : model->fields) {
    const ScalarField* truth = field_named(original_, f.info.name);
    ASSERT_NE(truth, nullptr) << f.info.name;
    const float peak = largest_magnitude(truth->steps[last]);
    ASSERT_GT(peak, 0) << f.info.name;
    for (const char* ratio : {"0.05", "0.25"}) {
      for (const char* aggregate : {"max", "mean"}) {
        const std::string out = dir_.file(std::string("r") + ratio + aggregate + ".vtu");
        auto extract = dynpm_cli("extract " + dpm + " --ratio " + ratio + " --step " +
                                 std::to_string(last) + " --aggregate " + aggregate + " -o " + out);
        ASSERT_EQ(extract.exit_code, 0) << extract.output;
        auto shown = read_mesh(out);
        ASSERT_TRUE(shown.ok()) << shown.message();
        EXPECT_LT(shown->topology.vertex_count, original_.topology.vertex_count / 2);
        const ScalarField* values = field_named(*shown, f.info.name);
        ASSERT_NE(values, nullptr) << f.info.name;
        const float largest = largest_magnitude(values->steps.at(0));
        if (std::string(aggregate) == "max")
          EXPECT_NEAR(largest, peak, f.max_error * 1.001 + 1e-6 * peak)
              << f.info.name << " at " << ratio;
        else
          EXPECT_LE(largest, peak + f.max_error * 1.001 + 1e-6 * peak)
              << f.info.name << " at " << ratio;
      }
    }
    auto full = dynpm_cli("extract " + dpm + " --full --step " + std::to_string(last) + " -o " +
                          dir_.file("full.vtk"));
    ASSERT_EQ(full.exit_code, 0) << full.output;
    // "--step last" names the same step without knowing the count.
    auto by_name = dynpm_cli("extract " + dpm + " --full --step last -o " + dir_.file("last.vtk"));
    ASSERT_EQ(by_name.exit_code, 0) << by_name.output;
    EXPECT_EQ(
        test::run_command("cmp " + dir_.file("full.vtk") + " " + dir_.file("last.vtk")).exit_code,
        0);
    auto back = read_mesh(dir_.file("full.vtk"));
    ASSERT_TRUE(back.ok()) << back.message();
    const ScalarField* values = field_named(*back, f.info.name);
    ASSERT_NE(values, nullptr) << f.info.name;
    ASSERT_EQ(values->steps.at(0).size(), truth->steps[last].size());
    for (size_t i = 0; i < truth->steps[last].size(); ++i)
      ASSERT_NEAR(values->steps[0][i], truth->steps[last][i], f.max_error * 1.001 + 1e-6 * peak)
          << f.info.name << " vertex " << i;
  }
}

TEST_F(CrashboxFields, ExtractRefusesAnUnknownAggregate) {
  auto build = dynpm_cli("build " + frd_ + " -o " + dir_.file("box.dpm"));
  ASSERT_EQ(build.exit_code, 0) << build.output;
  auto bad = dynpm_cli("extract " + dir_.file("box.dpm") +
                       " --ratio 0.1 --step 0 --aggregate sum -o " + dir_.file("x.vtk"));
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("--aggregate is max or mean"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace dynpm
