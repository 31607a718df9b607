// evaluate_levels(), the paper's Table 2 as a library call: on a bending sheet built in code, the
// full level is the original within the position bound, the coarsest level is not, the max
// column bounds every chosen step, and each cell is the Hausdorff distance it claims to be.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "dynpm/lod.h"
#include "dynpm/pipeline.h"
#include "fixtures.h"

namespace dynpm {
namespace {

// A 12 × 12 quad sheet that bends more at every step: z = (1 + t) · sin(x / 3) · cos(y / 4).
Animation bending_sheet(size_t steps) {
  const test::Mesh grid = test::quad_grid(12, 12);
  Animation a;
  a.topology = grid.topology;
  a.frames.set_vertex_count(grid.topology.vertex_count);
  for (size_t t = 0; t < steps; ++t) {
    std::vector<float> xyz = grid.positions;
    for (size_t v = 0; v < xyz.size() / 3; ++v)
      xyz[v * 3 + 2] =
          float((1.0 + double(t)) * std::sin(xyz[v * 3] / 3.0) * std::cos(xyz[v * 3 + 1] / 4.0));
    a.frames.add_step(std::move(xyz), double(t));
  }
  return a;
}

ProgressiveMesh build(const Animation& a) {
  auto mesh = build_progressive_mesh(a.topology, a.frames, BuildOptions{});
  EXPECT_TRUE(mesh.ok()) << mesh.message();
  return std::move(mesh).value();
}

LevelsOptions options_with(std::vector<double> ratios) {
  LevelsOptions options;
  options.ratios = std::move(ratios);
  options.hausdorff.face_samples = 4000;
  options.hausdorff.threads = 1;
  return options;
}

TEST(EvaluateLevels, RowsAndColumnsAreSortedAndTheDefaultStepsAreFirstMiddleLast) {
  const Animation a = bending_sheet(5);
  const ProgressiveMesh mesh = build(a);
  auto table = evaluate_levels(a.topology, a.frames, mesh, options_with({25, 5, 100, 25}));
  ASSERT_TRUE(table.ok()) << table.message();
  EXPECT_EQ(table->steps, (std::vector<size_t>{0, 2, 4}));
  EXPECT_EQ(table->reference_diagonal, mesh.diagonal());
  ASSERT_EQ(table->rows.size(), 3u);
  EXPECT_EQ(table->rows[0].ratio, 5);
  EXPECT_EQ(table->rows[1].ratio, 25);
  EXPECT_EQ(table->rows[2].ratio, 100);
  for (size_t i = 1; i < 3; ++i) {
    EXPECT_GE(table->rows[i].vertices, table->rows[i - 1].vertices);
    EXPECT_GE(table->rows[i].level, table->rows[i - 1].level);
  }
  for (const LevelRow& row : table->rows) EXPECT_EQ(row.steps.size(), 3u);
}

TEST(EvaluateLevels, TheFullLevelIsTheOriginalWithinThePositionBoundAndTheCoarsestIsNot) {
  const Animation a = bending_sheet(5);
  const ProgressiveMesh mesh = build(a);
  ASSERT_FALSE(mesh.lossless);
  auto table = evaluate_levels(a.topology, a.frames, mesh, options_with({2, 100}));
  ASSERT_TRUE(table.ok()) << table.message();
  const LevelRow& coarse = table->rows.front();
  const LevelRow& full = table->rows.back();
  EXPECT_EQ(full.vertices, a.topology.vertex_count);
  EXPECT_EQ(full.faces, a.topology.faces.size());
  // Every vertex within max_error of the original, so every point of every face (a quad's
  // centroid too) is: the distance is that bound, plus float rounding.
  const double bound_pct = 100 * mesh.max_error / table->reference_diagonal + 1e-4;
  for (const LevelDistance& cell : full.steps) EXPECT_LE(cell.hausdorff_pct, bound_pct);
  EXPECT_LE(full.max.hausdorff_pct, bound_pct);
  // A few vertices cannot follow a sheet bent this much.
  EXPECT_LT(coarse.vertices, a.topology.vertex_count / 10);
  EXPECT_GT(coarse.max.hausdorff_pct, 100 * bound_pct);
}

TEST(EvaluateLevels, TheMaxColumnBoundsEveryChosenStep) {
  const Animation a = bending_sheet(6);
  const ProgressiveMesh mesh = build(a);
  for (bool over_all : {true, false}) {
    SCOPED_TRACE(over_all ? "over all steps" : "over the chosen steps");
    LevelsOptions options = options_with({3, 10, 40});
    options.steps = {1, 3};
    options.max_over_all_steps = over_all;
    auto table = evaluate_levels(a.topology, a.frames, mesh, options);
    ASSERT_TRUE(table.ok()) << table.message();
    for (const LevelRow& row : table->rows) {
      double largest = 0;
      for (const LevelDistance& cell : row.steps) {
        EXPECT_GE(row.max.hausdorff_pct, cell.hausdorff_pct);
        EXPECT_GE(row.max.mean_pct, cell.mean_pct);
        EXPECT_GE(row.max.rms_pct, cell.rms_pct);
        largest = std::max(largest, cell.hausdorff_pct);
      }
      if (!over_all) {
        // Over the chosen steps only, the max is one of them.
        EXPECT_EQ(row.max.hausdorff_pct, largest);
        EXPECT_TRUE(row.max_step == 1 || row.max_step == 3) << row.max_step;
      }
      EXPECT_LT(row.max_step, a.frames.step_count());
    }
  }
}

TEST(EvaluateLevels, ACellIsHausdorffOfTheOriginalAndTheLevelAtThatStep) {
  const Animation a = bending_sheet(4);
  const ProgressiveMesh mesh = build(a);
  LevelsOptions options = options_with({10});
  options.steps = {3};
  auto table = evaluate_levels(a.topology, a.frames, mesh, options);
  ASSERT_TRUE(table.ok()) << table.message();
  const LevelRow& row = table->rows.front();

  Navigator nav(mesh);
  nav.set_level(row.level);
  std::vector<float> xyz(size_t{nav.vertex_count()} * 3);
  nav.positions(3.0, xyz);
  HausdorffOptions h = options.hausdorff;
  h.reference_diagonal = mesh.diagonal();
  auto direct = hausdorff(a.topology, a.frames.step(3), nav.topology(), xyz, h);
  ASSERT_TRUE(direct.ok()) << direct.message();
  EXPECT_EQ(row.steps[0].hausdorff_pct, direct->percent(direct->hausdorff));
  EXPECT_EQ(row.steps[0].mean_pct, direct->percent(direct->mean));
  EXPECT_EQ(row.steps[0].rms_pct, direct->percent(direct->rms));
}

TEST(EvaluateLevels, TheResultDependsOnTheSeedNotOnTheThreads) {
  const Animation a = bending_sheet(3);
  const ProgressiveMesh mesh = build(a);
  LevelsOptions one = options_with({5, 50});
  LevelsOptions two = one;
  two.hausdorff.threads = 2;
  auto first = evaluate_levels(a.topology, a.frames, mesh, one);
  auto second = evaluate_levels(a.topology, a.frames, mesh, two);
  ASSERT_TRUE(first.ok() && second.ok());
  for (size_t i = 0; i < first->rows.size(); ++i) {
    EXPECT_EQ(first->rows[i].max.hausdorff_pct, second->rows[i].max.hausdorff_pct);
    EXPECT_EQ(first->rows[i].max_step, second->rows[i].max_step);
    for (size_t k = 0; k < first->steps.size(); ++k)
      EXPECT_EQ(first->rows[i].steps[k].hausdorff_pct, second->rows[i].steps[k].hausdorff_pct);
  }
}

TEST(EvaluateLevels, AModelOfAnotherAnimationOrAStepPastTheEndIsAnError) {
  const Animation a = bending_sheet(3);
  const ProgressiveMesh mesh = build(a);
  LevelsOptions options = options_with({10});
  options.model_name = "sheet.dpm";

  const Animation other_mesh = test::quad_grid(3, 3).animation();
  auto r = evaluate_levels(other_mesh.topology, other_mesh.frames, mesh, options);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("sheet.dpm was built from another mesh"), std::string::npos)
      << r.message();

  const Animation longer = bending_sheet(4);
  r = evaluate_levels(longer.topology, longer.frames, mesh, options);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("sheet.dpm was built from another animation"), std::string::npos)
      << r.message();

  options.steps = {3};
  r = evaluate_levels(a.topology, a.frames, mesh, options);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.message().find("step 3"), std::string::npos) << r.message();
}

}  // namespace
}  // namespace dynpm

namespace dynpm {
namespace {

// The bending sheet with a node field "hot": 0 everywhere but one inner vertex, whose value grows
// with the step: the peak a coarse level must not hide.
class HotSpot final : public FrameSource {
 public:
  explicit HotSpot(const Frames& frames) : frames_(frames) {}
  uint32_t vertex_count() const override { return frames_.vertex_count(); }
  size_t step_count() const override { return frames_.step_count(); }
  double step_time(size_t t) const override { return frames_.step_time(t); }
  Status read_step(size_t t, std::span<float> out) const override {
    return frames_.read_step(t, out);
  }
  std::vector<FieldInfo> fields() const override { return {{"hot", FieldLocation::kNode, ""}}; }
  Status read_field(size_t, size_t t, std::span<float> out) const override {
    std::fill(out.begin(), out.end(), 0.f);
    out[kHot] = 5.f + float(t);
    return {};
  }
  static constexpr uint32_t kHot = 6 * 13 + 7;  // vertex (7, 6) of the 12 × 12 sheet

 private:
  const Frames& frames_;
};

TEST(EvaluateLevels, WithTheMaxAggregateThePeakIsKeptAtEveryLevelWithTheMeanNot) {
  const Animation a = bending_sheet(3);
  const HotSpot frames(a.frames);
  auto mesh = build_progressive_mesh(a.topology, frames, BuildOptions{});
  ASSERT_TRUE(mesh.ok()) << mesh.message();
  LevelsOptions options = options_with({3, 20, 100});
  options.fields = {"hot"};
  auto table = evaluate_levels(a.topology, frames, *mesh, options);
  ASSERT_TRUE(table.ok()) << table.message();
  EXPECT_EQ(table->field_ranges, std::vector<double>{7});
  // The file keeps values within max_error (0.1 % of the range by default); the peak is ≥ 5.
  const double within = mesh->fields[0].max_error / 5 * 1.0001;
  for (const LevelRow& row : table->rows) {
    for (const LevelDistance& cell : row.steps) {
      ASSERT_EQ(cell.peak_ratio.size(), 1u);
      EXPECT_NEAR(cell.peak_ratio[0], 1, within);
      EXPECT_LE(std::abs(cell.peak_gap_pct[0]), 100 * mesh->fields[0].max_error / 7 * 1.0001);
      EXPECT_GE(row.max.field_error_pct[0], cell.field_error_pct[0]);
    }
    EXPECT_NEAR(row.max.peak_ratio[0], 1, within);
  }
  // The full level is the original (positions within the bound): almost no field error. A
  // coarse level spreads the peak over a wider area than the original's one vertex.
  EXPECT_LT(table->rows.back().max.field_error_pct[0], 0.1);
  EXPECT_GT(table->rows.front().max.field_error_pct[0], 10);

  options.aggregate = FieldAggregate::kMean;
  auto mean = evaluate_levels(a.topology, frames, *mesh, options);
  ASSERT_TRUE(mean.ok()) << mean.message();
  EXPECT_LT(mean->rows.front().max.peak_ratio[0], 0.5);
  EXPECT_NEAR(mean->rows.back().max.peak_ratio[0], 1, within);

  // The same numbers on two threads.
  options.hausdorff.threads = 2;
  auto two = evaluate_levels(a.topology, frames, *mesh, options);
  ASSERT_TRUE(two.ok()) << two.message();
  for (size_t i = 0; i < mean->rows.size(); ++i)
    EXPECT_EQ(two->rows[i].max.field_error_pct, mean->rows[i].max.field_error_pct);

  options.fields = {"cold"};
  auto missing = evaluate_levels(a.topology, frames, *mesh, options);
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.message().find("the original has no field 'cold'"), std::string::npos)
      << missing.message();
}

}  // namespace
}  // namespace dynpm
