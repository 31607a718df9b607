// Family files (docs/family.md) on real data: the CalculiX crash box of ../shared/data and
// second CalculiX runs of the very same mesh under other loads (bench/family/crashbox-bent.frd.gz
// and crashbox-short.frd.gz, made by bench/family/make_crashbox_variant.py), built into one
// hierarchy by the command line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dynpm/io.h"
#include "dynpm/lod.h"
#include "dynpm/pipeline.h"
#include "dynpm/progressive.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

test::CommandResult dynpm_cli(const std::string& arguments) {
  return test::run_command(std::string(DYNPM_CLI) + " " + arguments);
}

std::string unpack(const std::string& gz, const std::string& frd) {
  if (std::system(("zcat '" + gz + "' > '" + frd + "' 2>/dev/null").c_str()) != 0) return "";
  return frd;
}

Animation load(const std::string& path) {
  auto stream = open_input(std::vector<std::string>{path});
  EXPECT_TRUE(stream.ok()) << stream.message();
  auto all = load_all_steps(std::move(stream).value());
  EXPECT_TRUE(all.ok()) << all.message();
  return std::move(all).value();
}

class CrashboxFamily : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new test::TempDir;
    crush_ =
        unpack(test::shared_data() + "/crashbox-s/crashbox-s.frd.gz", dir_->file("crashbox-s.frd"));
    bent_ = unpack(test::source_dir() + "/bench/family/crashbox-bent.frd.gz",
                   dir_->file("crashbox-bent.frd"));
    if (crush_.empty() || bent_.empty()) return;
    family_ = dir_->file("family.dpm");
    build_ = dynpm_cli("build --family '" + crush_ + "' '" + bent_ + "' -o '" + family_ + "'");
  }
  static void TearDownTestSuite() { delete dir_; }
  void SetUp() override {
    if (crush_.empty()) GTEST_SKIP() << "../shared/data/crashbox-s is missing";
    ASSERT_FALSE(bent_.empty()) << "bench/family/crashbox-bent.frd.gz is missing";
    ASSERT_EQ(build_.exit_code, 0) << build_.output;
  }

  static inline test::TempDir* dir_ = nullptr;
  static inline std::string crush_, bent_, family_;
  static inline test::CommandResult build_;
};

TEST_F(CrashboxFamily, StoresTheSharedUndeformedStepOnce) {
  auto mesh = read_dpm(family_);
  ASSERT_TRUE(mesh.ok()) << mesh.message();
  ASSERT_EQ(mesh->variants.size(), 2u);
  EXPECT_EQ(mesh->variants[0].name, "crashbox-s");
  EXPECT_EQ(mesh->variants[1].name, "crashbox-bent");
  EXPECT_EQ(mesh->variants[0].steps.size(), 26u);
  EXPECT_EQ(mesh->variants[1].steps.size(), 13u);
  // The undeformed step is the same floats in both runs: stored once; every other step is not.
  EXPECT_EQ(mesh->variants[1].steps[0], mesh->variants[0].steps[0]);
  EXPECT_EQ(mesh->step_count(), 26u + 13u - 1u);
}

// Fully refined, each variant is its own input at every step (within the position bound),
// in the input's order, at the input's times.
TEST_F(CrashboxFamily, EachVariantAtFullResolutionIsItsInput) {
  auto family = read_dpm(family_);
  ASSERT_TRUE(family.ok()) << family.message();
  const std::string inputs[] = {crush_, bent_};
  for (size_t k = 0; k < 2; ++k) {
    SCOPED_TRACE(inputs[k]);
    const Animation original = load(inputs[k]);
    ProgressiveMesh mesh = *family;
    select_variant(mesh, k);
    ASSERT_EQ(mesh.step_count(), original.frames.step_count());
    Navigator nav(mesh);
    nav.set_level(mesh.split_count());
    auto order = original_order(nav);
    ASSERT_TRUE(order.ok()) << order.message();
    std::vector<float> xyz(size_t{nav.vertex_count()} * 3), step(xyz.size());
    double worst = 0;
    for (size_t t = 0; t < mesh.step_count(); ++t) {
      EXPECT_EQ(mesh.times[t], original.frames.step_time(t));
      nav.positions(double(t), xyz);
      ASSERT_TRUE(original.frames.read_step(t, step).ok());
      for (uint32_t v = 0; v < original.topology.vertex_count; ++v)
        for (int c = 0; c < 3; ++c)
          worst = std::max(worst, double(std::abs(xyz[order->vertex_of_original[v] * 3 + c] -
                                                  step[size_t{v} * 3 + c])));
    }
    EXPECT_LE(worst, mesh.max_error * 1.0001 + 1e-6) << "the bound is " << mesh.max_error;
    EXPECT_GT(worst, 0.0);  // positions are quantized: the comparison sees them
  }
}

// One hierarchy: any level is the same vertices and faces in every variant.
TEST_F(CrashboxFamily, AnyLevelIsTheSameMeshInEveryVariant) {
  auto family = read_dpm(family_);
  ASSERT_TRUE(family.ok()) << family.message();
  ProgressiveMesh a = *family, b = *family;
  select_variant(a, 0);
  select_variant(b, 1);
  Navigator na(a), nb(b);
  for (double ratio : {0.05, 0.25, 1.0}) {
    const auto n = static_cast<uint32_t>(std::lround(ratio * a.full_vertex_count));
    na.set_vertex_count(n);
    nb.set_vertex_count(n);
    EXPECT_EQ(na.vertex_count(), nb.vertex_count());
    const Topology ta = na.topology(), tb = nb.topology();
    ASSERT_EQ(ta.faces.size(), tb.faces.size());
    for (size_t f = 0; f < ta.faces.size(); ++f) ASSERT_EQ(ta.faces[f].v, tb.faces[f].v);
    // ... and the variants differ in where those vertices are at their last step.
    std::vector<float> pa(size_t{na.vertex_count()} * 3), pb(pa.size());
    na.positions(double(a.step_count() - 1), pa);
    nb.positions(double(b.step_count() - 1), pb);
    EXPECT_NE(pa, pb);
  }
}

// A reader that does not know VARI skips it (an optional chunk, docs/FORMAT.md) and reads the
// stored steps as one animation.
TEST_F(CrashboxFamily, AReaderThatIgnoresVariStillReadsTheFile) {
  std::ifstream in(family_, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t at = bytes.find("VARI");
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at, 4, "VARX");  // a tag this reader does not know; the checksum covers the payload
  auto mesh = decode_dpm(bytes, "renamed.dpm");
  ASSERT_TRUE(mesh.ok()) << mesh.message();
  EXPECT_TRUE(mesh->complete);
  EXPECT_TRUE(mesh->variants.empty());
  EXPECT_EQ(mesh->step_count(), 38u);
}

TEST_F(CrashboxFamily, CommandsTakeAVariantByNameOrIndex) {
  const std::string out = dir_->file("bent_{:03d}.obj");
  auto r = dynpm_cli("extract '" + family_ + "' --full --variant crashbox-bent -o '" + out + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(std::filesystem::exists(dir_->file("bent_012.obj")));
  EXPECT_FALSE(std::filesystem::exists(dir_->file("bent_013.obj")));
  // Without --variant: variant 0, and a note says so.
  r = dynpm_cli("extract '" + family_ + "' --ratio 0.1 --step 25 -o '" + dir_->file("s.obj") + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("showing variant 0, crashbox-s"), std::string::npos) << r.output;
  r = dynpm_cli("extract '" + family_ + "' --full --variant 2 --step 0 -o '" + dir_->file("x.obj") +
                "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("0 crashbox-s, 1 crashbox-bent"), std::string::npos) << r.output;
  r = dynpm_cli("info '" + family_ + "' --variant 1 --json");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("\"steps\": 13"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"shared_steps\": 1"), std::string::npos) << r.output;
  // eval against the variant's own input.
  r = dynpm_cli("eval '" + bent_ + "' --dpm '" + family_ +
                "' --variant crashbox-bent --ratios 25 --steps 12");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = dynpm_cli("eval '" + bent_ + "' --dpm '" + family_ + "' --ratios 25 --steps 12");
  EXPECT_EQ(r.exit_code, 1) << r.output;  // variant 0 has 26 steps: not built from this input
}

// One step of a variant: variant 0's steps are stored reversed (docs/family.md), so its step T is
// not among the stored steps up to T; extract reads what that step needs, whatever the variant.
TEST_F(CrashboxFamily, ExtractOfOneStepIsThatStepOfTheVariant) {
  auto family = read_dpm(family_);
  ASSERT_TRUE(family.ok()) << family.message();
  const std::string inputs[] = {crush_, bent_};
  for (size_t k = 0; k < 2; ++k) {
    const Animation original = load(inputs[k]);
    for (size_t t : {size_t{0}, size_t{3}, size_t{12}}) {
      SCOPED_TRACE(inputs[k] + ", step " + std::to_string(t));
      const std::string out = dir_->file("one_step.obj");
      const std::string variant = k == 0 ? "" : " --variant 1";
      auto r = dynpm_cli("extract '" + family_ + "' --full --step " + std::to_string(t) + variant +
                         " -o '" + out + "'");
      ASSERT_EQ(r.exit_code, 0) << r.output;
      const Animation extracted = load(out);
      ASSERT_EQ(extracted.topology.vertex_count, original.topology.vertex_count);
      std::vector<float> got(size_t{original.topology.vertex_count} * 3), want(got.size());
      ASSERT_TRUE(extracted.frames.read_step(0, got).ok());
      ASSERT_TRUE(original.frames.read_step(t, want).ok());
      double worst = 0;
      for (size_t i = 0; i < got.size(); ++i)
        worst = std::max(worst, double(std::abs(got[i] - want[i])));
      EXPECT_LE(worst, family->max_error * 1.0001 + 1e-6);
    }
  }
}

// A variant's steps up to T, read in one pass (DpmReadLimits::variant): the stored steps decoded
// are those up to the last one its steps 0 … T use, no more (variant 0's are stored reversed, so
// its step 0 is its last stored step; the bend's follow), and what they show is what the whole
// file shows. Without a variant, last_step = 0 ('batch', the catalogue) is one stored step.
TEST_F(CrashboxFamily, AVariantsStepsAreReadInOnePass) {
  auto whole = read_dpm(family_);
  ASSERT_TRUE(whole.ok()) << whole.message();
  const size_t stored = whole->step_count();
  for (size_t k = 0; k < 2; ++k)
    for (size_t t : {size_t{0}, size_t{3}, size_t{12}}) {
      SCOPED_TRACE("variant " + std::to_string(k) + ", step " + std::to_string(t));
      DpmReadLimits limits;
      limits.variant = k == 0 ? "crashbox-s" : "1";
      limits.last_step = t;
      auto mesh = read_dpm(family_, limits);
      ASSERT_TRUE(mesh.ok()) << mesh.message();
      const std::vector<uint32_t>& steps = whole->variants[k].steps;
      const size_t needed = *std::max_element(steps.begin(), steps.begin() + t + 1) + 1;
      EXPECT_EQ(mesh->steps_read, needed);
      // The crush's 26 steps stored first, its step 0 last of them; the bend's step t after it.
      EXPECT_EQ(needed, k == 0 ? 26u : 26u + t);
      for (size_t s = 0; s < stored; ++s)
        EXPECT_EQ(mesh->positions[s].empty(), s >= needed) << "stored step " << s;
      EXPECT_EQ(mesh->variants.size(), 2u);  // the reader does not choose; select_variant() does
      ProgressiveMesh all = *whole;
      select_variant(*mesh, k);
      select_variant(all, k);
      ASSERT_GE(mesh->steps_read, t + 1);
      for (size_t u = 0; u <= t; ++u) EXPECT_EQ(mesh->positions[u], all.positions[u]);
    }
  DpmReadLimits first;
  first.last_step = 0;
  auto one = read_dpm(family_, first);
  ASSERT_TRUE(one.ok()) << one.message();
  EXPECT_EQ(one->steps_read, 1u);
  DpmReadLimits unknown;
  unknown.variant = "crashbox-x";
  auto refused = read_dpm(family_, unknown);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.message().find("no variant 'crashbox-x' (the variants: 0 crashbox-s, 1 "
                                   "crashbox-bent)"),
            std::string::npos)
      << refused.message();
}

// 'extract --step' and '--refine' of a family file open it once (strace counts the opens), and
// write what the whole file gives at that step: byte for byte the file that an extract of every
// step writes for it.
TEST_F(CrashboxFamily, ExtractOfAStepOpensTheFileOnce) {
  if (test::run_command("strace -o /dev/null true").exit_code != 0)
    GTEST_SKIP() << "strace cannot run here: the opens are not counted";
  const std::string trace = dir_->file("opens.txt");
  // LeakSanitizer cannot run under ptrace: the sanitizer lane's traced runs check no leaks.
  const std::string strace =
      "ASAN_OPTIONS=\"$ASAN_OPTIONS:detect_leaks=0\" strace -f -e trace=openat -o '" + trace + "' ";
  const auto opens = [&]() {
    std::ifstream in(trace);
    size_t count = 0;
    for (std::string line; std::getline(in, line);)
      count += line.find("family.dpm\"") != std::string::npos && line.find("= -1") == line.npos;
    return count;
  };
  const auto read_all = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  for (const std::string variant : {"", " --variant 1"}) {
    SCOPED_TRACE(variant.empty() ? "variant 0" : variant);
    auto r = dynpm_cli("extract '" + family_ + "' --ratio 0.2" + variant + " -o '" +
                       dir_->file("every_{:03d}.vtu") + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    for (const std::string t : {"0", "3", "12"}) {
      const std::string one = dir_->file("one.vtu");
      r = test::run_command(strace + DYNPM_CLI + " extract '" + family_ + "' --ratio 0.2 --step " +
                            t + variant + " -o '" + one + "'");
      ASSERT_EQ(r.exit_code, 0) << r.output;
      EXPECT_EQ(opens(), 1u) << "step " << t;
      char every[32];
      std::snprintf(every, sizeof every, "every_%03d.vtu", std::stoi(t));
      EXPECT_EQ(read_all(one), read_all(dir_->file(every))) << "step " << t;
    }
    r = test::run_command(strace + DYNPM_CLI + " extract '" + family_ +
                          "' --refine box:0,0,0,50,50,250 --elsewhere 5%" + " --step 5" + variant +
                          " -o '" + dir_->file("refined.obj") + "'");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(opens(), 1u) << "--refine";
  }
}

// The largest Hausdorff distance over every step, absolute, of `model` at each of `ratios` (%),
// measured as bench/family/family_bench.py does (eval's defaults, every step).
std::vector<double> hausdorff(const std::string& input, const ProgressiveMesh& model,
                              std::vector<double> ratios) {
  const Animation original = load(input);
  LevelsOptions options;
  options.ratios = std::move(ratios);
  for (size_t t = 0; t < original.frames.step_count(); ++t) options.steps.push_back(t);
  options.hausdorff.threads = 2;
  auto table = evaluate_levels(original.topology, original.frames, model, options);
  EXPECT_TRUE(table.ok()) << table.message();
  std::vector<double> out;
  if (table.ok())
    for (const LevelRow& row : table->rows)
      out.push_back(row.max.hausdorff_pct * table->reference_diagonal / 100);
  return out;
}

// Variant k's largest Hausdorff distance at 5 % and 25 % in `family` and in its own build.
struct VariantErrors {
  std::vector<double> in_family, alone;
};
VariantErrors errors_of_variant(const std::string& family_path, const std::string& input, size_t k,
                                const std::string& separate) {
  VariantErrors e;
  auto r = dynpm_cli("build '" + input + "' -o '" + separate + "' --no-thumbnail");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  auto family = read_dpm(family_path);
  auto own = read_dpm(separate);
  if (!family.ok() || !own.ok()) {
    ADD_FAILURE() << family.message() << own.message();
    return e;
  }
  select_variant(*family, k);
  e.in_family = hausdorff(input, *family, {5, 25});
  e.alone = hausdorff(input, *own, {5, 25});
  EXPECT_EQ(e.in_family.size(), 2u);
  EXPECT_EQ(e.alone.size(), 2u);
  return e;
}

// Each variant's error in the family against its own separate build (docs/family.md,
// "Measured", 2026-12-03): the crush keeps within the 10 % (1.079 at 5 %, 0.390 at
// 25 %); the bend does not (1.51 at 5 %, 10.8 at 25 %: the two keep different vertices) but stays
// small in absolute terms (0.22 % of the diagonal at 25 %). Bounds a little above those.
TEST_F(CrashboxFamily, EachVariantsErrorAgainstItsSeparateBuild) {
  auto family = read_dpm(family_);
  ASSERT_TRUE(family.ok()) << family.message();
  const VariantErrors crush = errors_of_variant(family_, crush_, 0, dir_->file("alone.dpm"));
  const VariantErrors bent = errors_of_variant(family_, bent_, 1, dir_->file("alone.dpm"));
  ASSERT_EQ(crush.in_family.size() + bent.in_family.size(), 4u);
  EXPECT_LE(crush.in_family[0], 1.10 * crush.alone[0]);
  EXPECT_LE(crush.in_family[1], 1.10 * crush.alone[1]);
  EXPECT_LE(bent.in_family[0], 1.60 * bent.alone[0]);
  EXPECT_LE(bent.in_family[1], 0.003 * family->diagonal());
}

// A DOE over the crush depth: the crush beside a short crush of the same mesh (4.8 mm instead of
// 60, bench/family/crashbox-short.frd.gz). Measured 2026-12-03: the crush at 25 % 1.000 × its
// separate build, the short crush at 5 % 0.974 × (the other two miss: docs/family.md).
TEST_F(CrashboxFamily, AShortCrushBesideTheCrush) {
  const std::string short_crush = unpack(test::source_dir() + "/bench/family/crashbox-short.frd.gz",
                                         dir_->file("crashbox-short.frd"));
  ASSERT_FALSE(short_crush.empty()) << "bench/family/crashbox-short.frd.gz is missing";
  const std::string doe = dir_->file("doe.dpm");
  auto r = dynpm_cli("build --family '" + crush_ + "' '" + short_crush + "' -o '" + doe +
                     "' --no-thumbnail");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto family = read_dpm(doe);
  ASSERT_TRUE(family.ok()) << family.message();
  EXPECT_EQ(family->step_count(), 26u + 9u - 1u);  // the undeformed step stored once
  const VariantErrors crush = errors_of_variant(doe, crush_, 0, dir_->file("alone.dpm"));
  const VariantErrors shallow = errors_of_variant(doe, short_crush, 1, dir_->file("alone.dpm"));
  ASSERT_EQ(crush.in_family.size() + shallow.in_family.size(), 4u);
  EXPECT_LE(crush.in_family[1], 1.10 * crush.alone[1]);
  EXPECT_LE(shallow.in_family[0], 1.10 * shallow.alone[0]);
  EXPECT_LE(crush.in_family[0], 1.60 * crush.alone[0]);
}

// Meshes that differ are refused before any work, the first difference named; nothing written.
TEST_F(CrashboxFamily, AnotherMeshIsRefusedWithTheFirstDifference) {
  std::ifstream in(crush_);
  std::stringstream text;
  text << in.rdbuf();
  std::string frd = text.str();
  // Element 17's last two corners swapped.
  const size_t at = frd.find("\n -1        17    9");
  ASSERT_NE(at, std::string::npos);
  const size_t line = frd.find('\n', at + 1) + 1, end = frd.find('\n', line);
  std::istringstream corners(frd.substr(line + 3, end - line - 3));
  long a, b, c, d;
  corners >> a >> b >> c >> d;
  char swapped[64];
  std::snprintf(swapped, sizeof swapped, " -2%10ld%10ld%10ld%10ld", a, b, d, c);
  frd.replace(line, end - line, swapped);
  const std::string other = dir_->file("swapped.frd"), out = dir_->file("refused.dpm");
  std::ofstream(other) << frd;
  auto r = dynpm_cli("build --family '" + crush_ + "' '" + other + "' -o '" + out + "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("swapped.frd is not a variant of crashbox-s.frd's mesh: element 17 has "
                          "nodes " +
                          std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(d)),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
  // Each later input is compared as it is opened (then its faces are freed): the difference is
  // told before a third input is even looked for.
  const std::string missing = dir_->file("not-there.frd");
  r = dynpm_cli("build --family '" + crush_ + "' '" + other + "' '" + missing + "' -o '" + out +
                "'");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("swapped.frd is not a variant of crashbox-s.frd's mesh"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("not-there.frd"), std::string::npos) << r.output;
  EXPECT_FALSE(std::filesystem::exists(out));
}

}  // namespace
}  // namespace dynpm
