// Reading only what is asked (DpmReadLimits, docs/FORMAT.md "SPLT payload"): a level and a step
// read from the CalculiX crash box's .dpm show exactly what the whole file shows there, and the
// reader never looks at the chunks after the level it needs.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>

#include "dynpm/core.h"
#include "dynpm/lod.h"
#include "dynpm/progressive.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

class ReadLimits : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string gz = test::shared_data() + "/crashbox-fields/crashbox-fields.frd.gz";
    const std::string frd = dir_.file("crashbox-fields.frd");
    if (std::system(("zcat '" + gz + "' > '" + frd + "' 2>/dev/null").c_str()) != 0)
      GTEST_SKIP() << "../shared/data/crashbox-fields is missing";
    dpm_ = dir_.file("box.dpm");
    const auto built = test::run_command(std::string(DYNPM_CLI) + " build '" + frd + "' -o '" +
                                         dpm_ + "' --key-steps auto:3");
    ASSERT_EQ(built.exit_code, 0) << built.output;
    auto full = read_dpm(dpm_);
    ASSERT_TRUE(full.ok()) << full.message();
    full_ = std::move(full).value();
    ASSERT_FALSE(full_.fields.empty());
  }

  ProgressiveMesh limited(const DpmReadLimits& limits, const std::string& path = {}) {
    auto m = read_dpm(path.empty() ? dpm_ : path, limits);
    EXPECT_TRUE(m.ok()) << m.message();
    return m.ok() ? std::move(m).value() : ProgressiveMesh{};
  }

  // The level's faces and its positions at step t, as the navigator shows them.
  static std::pair<std::vector<Face>, std::vector<float>> shown(const ProgressiveMesh& m,
                                                                uint32_t level, double t) {
    Navigator nav(m);
    nav.set_level(level);
    std::vector<float> xyz(size_t{nav.vertex_count()} * 3);
    nav.positions(t, xyz);
    return {nav.topology().faces, xyz};
  }

  test::TempDir dir_;
  std::string dpm_;
  ProgressiveMesh full_;
};

TEST_F(ReadLimits, ALevelReadAloneShowsWhatTheWholeFileShowsThere) {
  const uint32_t b = full_.base_vertex_count;
  const double diagonal = full_.diagonal();
  struct Case {
    DpmReadLimits limits;
    uint32_t level;  // the navigator's level on the whole file for the same request
  };
  std::vector<Case> cases;
  auto add = [&](DpmReadLimits l, uint32_t level) {
    l.fields = false;
    l.last_step = 7;
    cases.push_back({l, level});
  };
  DpmReadLimits by_count;
  by_count.vertices = b + 300;
  add(by_count, 300);
  DpmReadLimits by_ratio;
  by_ratio.ratio = 0.05;
  add(by_ratio, static_cast<uint32_t>(std::lround(0.05 * full_.full_vertex_count)) - b);
  for (double e : {0.01 * diagonal, double(full_.error[1000])}) {
    Navigator nav(full_);
    nav.set_error(e);
    DpmReadLimits by_error;
    by_error.error = e;
    add(by_error, nav.level());
  }
  DpmReadLimits in_percent;
  in_percent.error = 0.01;
  in_percent.error_of_diagonal = true;
  add(in_percent, cases[2].level);
  for (const Case& c : cases) {
    SCOPED_TRACE(c.level);
    const ProgressiveMesh m = limited(c.limits);
    EXPECT_EQ(m.split_count(), c.level);
    EXPECT_TRUE(m.limited);
    EXPECT_FALSE(m.complete);
    EXPECT_TRUE(m.fields.empty());  // not asked for: checked, not decoded
    EXPECT_EQ(m.steps_read, 8u);
    for (double t : {0.0, 7.0, 6.5}) EXPECT_EQ(shown(m, c.level, t), shown(full_, c.level, t));
    EXPECT_TRUE(m.positions[8].empty());
  }
}

TEST_F(ReadLimits, WithFieldsEverySplitIsReadSoThatPeaksStayAndLaterStepsAreNot) {
  DpmReadLimits l;
  l.ratio = 0.05;
  l.last_step = 3;
  const ProgressiveMesh m = limited(l);
  EXPECT_EQ(m.split_count(), full_.split_count());
  ASSERT_EQ(m.fields.size(), full_.fields.size());
  // Steps 0 … 3 decoded as a full read decodes them (their sections only: FORMAT.md "Fields").
  for (size_t f = 0; f < m.fields.size(); ++f)
    for (size_t t = 0; t < m.step_count(); ++t) {
      EXPECT_EQ(m.fields[f].values[t].empty(), t > 3) << f << " " << t;
      if (t <= 3) {
        EXPECT_TRUE(m.fields[f].values[t] == full_.fields[f].values[t]) << f << " " << t;
      }
    }
  Navigator a(m), b(full_);
  const uint32_t level = full_.split_count() / 20;
  a.set_level(level);
  b.set_level(level);
  std::vector<float> va(a.vertex_count()), vb(b.vertex_count());
  a.field_values(0, 3, va);
  b.field_values(0, 3, vb);
  EXPECT_EQ(va, vb);
}

TEST_F(ReadLimits, TheChunksAfterTheLevelAreNeverRead) {
  // Damage the last byte before END (inside the last SPLT or FLDS): the whole file is refused,
  // a coarse level of it is not, since its reader stops before.
  std::ifstream in(dpm_, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  bytes[bytes.size() - 25] ^= 0x40;
  const std::string damaged = dir_.file("damaged.dpm");
  std::ofstream(damaged, std::ios::binary) << bytes;
  EXPECT_FALSE(read_dpm(damaged).ok());
  DpmReadLimits l;
  l.ratio = 0.05;
  l.fields = false;
  const ProgressiveMesh m = limited(l, damaged);
  EXPECT_EQ(m.vertex_count(), std::lround(0.05 * full_.full_vertex_count));
}

TEST_F(ReadLimits, TheWholeLevelAskedForIsTheCompleteFile) {
  DpmReadLimits l;
  l.ratio = 1.0;
  const ProgressiveMesh m = limited(l);
  EXPECT_TRUE(m.complete);
  EXPECT_EQ(m.split_count(), full_.split_count());
}

}  // namespace
}  // namespace dynpm
