// Result fields in the cost and the shape regularizer (docs/simplify.md, "Fields in the cost",
// "Shape"): weight 0 is the geometry-only cost byte for byte, fields in the cost lower the field
// error on the CalculiX crash box with stress and plastic strain (per node; the jump allowance
// keeps the hinges), an element field's edge survives as a line of vertices, unknown field
// names are refused naming the others, and the
// regularizer keeps a flat plate's triangles well shaped.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "dynpm/eval.h"
#include "dynpm/io.h"
#include "dynpm/simplify.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

// A FrameSource seen without its fields: what the geometry-only cost sees.
class WithoutFields final : public FrameSource {
 public:
  explicit WithoutFields(const FrameSource& frames) : frames_(frames) {}
  uint32_t vertex_count() const override { return frames_.vertex_count(); }
  size_t step_count() const override { return frames_.step_count(); }
  double step_time(size_t t) const override { return frames_.step_time(t); }
  Status read_step(size_t t, std::span<float> out) const override {
    return frames_.read_step(t, out);
  }

 private:
  const FrameSource& frames_;
};

// Frames with one field, the same values in every step: per face (EPS) or per node (TEMP).
class WithField final : public FrameSource {
 public:
  WithField(const Frames& frames, std::vector<float> values,
            FieldLocation location = FieldLocation::kElement)
      : frames_(frames), values_(std::move(values)), location_(location) {}
  uint32_t vertex_count() const override { return frames_.vertex_count(); }
  size_t step_count() const override { return frames_.step_count(); }
  double step_time(size_t t) const override { return frames_.step_time(t); }
  Status read_step(size_t t, std::span<float> out) const override {
    return frames_.read_step(t, out);
  }
  std::vector<FieldInfo> fields() const override {
    return {{location_ == FieldLocation::kElement ? "EPS" : "TEMP", location_, ""}};
  }
  Status read_field(size_t, size_t, std::span<float> out) const override {
    std::copy(values_.begin(), values_.end(), out.begin());
    return {};
  }

 private:
  const Frames& frames_;
  std::vector<float> values_;
  FieldLocation location_;
};

constexpr FieldForm kForms[] = {FieldForm::kSpread, FieldForm::kAttributes, FieldForm::kQuadric};

// v0 → v1 of every collapse, and each input vertex's ancestor at the end.
class Trace final : public CollapseListener {
 public:
  explicit Trace(uint32_t n) : parent_(n, kNoVertex) {}
  void on_collapse(const CollapseRecord& r) override {
    parent_[r.v0] = r.v1;
    pairs.push_back({r.v0, r.v1});
  }
  uint32_t ancestor(uint32_t v) const {
    while (parent_[v] != kNoVertex) v = parent_[v];
    return v;
  }
  std::vector<std::pair<uint32_t, uint32_t>> pairs;

 private:
  std::vector<uint32_t> parent_;
};

std::string crashbox_fields(const test::TempDir& dir) {
  const std::string gz = test::shared_data() + "/crashbox-fields/crashbox-fields.frd.gz";
  if (!std::filesystem::exists(gz)) return "";
  const std::string frd = dir.file("crashbox-fields.frd");
  EXPECT_EQ(test::run_command("gzip -dc '" + gz + "' > '" + frd + "'").exit_code, 0);
  return frd;
}

// The largest difference, over every step and input vertex u, between u's value and the value
// of largest magnitude among those its ancestor stands for, in parts of the field's range.
double field_error(const FrameSource& frames, size_t field, const Trace& trace) {
  const uint32_t n = frames.vertex_count();
  std::vector<uint32_t> ancestor(n);
  for (uint32_t v = 0; v < n; ++v) ancestor[v] = trace.ancestor(v);
  std::vector<std::vector<float>> values(frames.step_count(), std::vector<float>(n));
  double lo = HUGE_VAL, hi = -HUGE_VAL, worst = 0;
  for (size_t t = 0; t < values.size(); ++t) {
    EXPECT_TRUE(frames.read_field(field, t, values[t]).ok());
    for (float x : values[t]) lo = std::min(lo, double{x}), hi = std::max(hi, double{x});
  }
  for (const std::vector<float>& f : values) {
    std::vector<float> shown(n, 0.0f);
    for (uint32_t u = 0; u < n; ++u)
      if (std::fabs(f[u]) > std::fabs(shown[ancestor[u]])) shown[ancestor[u]] = f[u];
    for (uint32_t u = 0; u < n; ++u)
      worst = std::max(worst, std::fabs(double{shown[ancestor[u]]} - f[u]));
  }
  return worst / (hi - lo);
}

TEST(SimplifyFields, WeightZeroIsTheGeometryOnlyCostExactly) {
  test::TempDir dir;
  const std::string frd = crashbox_fields(dir);
  if (frd.empty()) GTEST_SKIP() << "../shared/data is not beside the project";
  auto input = open_input(std::vector<std::string>{frd});
  ASSERT_TRUE(input) << input.message();
  ASSERT_GE(input->frames->fields().size(), 2u);
  const WithoutFields geometry(*input->frames);
  for (double regularize : {0.0, 0.001}) {
    SimplifyOptions options;
    options.target_ratio = 0.25;
    options.regularize = regularize;
    options.field_weight = 0;
    Trace with(input->topology.vertex_count), without(input->topology.vertex_count);
    auto a = simplify(input->topology, *input->frames, options, &with);
    options.field_weight = 1;  // no field to weigh
    auto b = simplify(input->topology, geometry, options, &without);
    ASSERT_TRUE(a && b);
    EXPECT_EQ(with.pairs, without.pairs);
    EXPECT_EQ(a->topology.faces, b->topology.faces);
    EXPECT_EQ(a->max_error, b->max_error);
    // Weight 0 reads no field, whatever the field term's form and combination.
    for (FieldForm form : kForms)
      for (FieldCombine combine : {FieldCombine::kAdd, FieldCombine::kScale}) {
        SimplifyOptions zero = options;
        zero.field_weight = 0, zero.field_form = form, zero.field_combine = combine;
        Trace trace(input->topology.vertex_count);
        ASSERT_TRUE(simplify(input->topology, *input->frames, zero, &trace));
        EXPECT_EQ(trace.pairs, without.pairs) << int(form) << " " << int(combine);
      }
    // With the fields in the cost, other collapses are chosen.
    Trace fields(input->topology.vertex_count);
    options.field_weight = kDefaultFieldWeight;
    ASSERT_TRUE(simplify(input->topology, *input->frames, options, &fields));
    EXPECT_NE(fields.pairs, without.pairs);
  }
}

// The simplifier's own field error (each vertex's spread, every step): the added term at 0.01
// lowers it to under 0.75 × the geometry-only one; the default (scaled) never makes it worse.
TEST(SimplifyFields, FieldsInTheCostLowerTheFieldErrorOnTheCrashBox) {
  test::TempDir dir;
  const std::string frd = crashbox_fields(dir);
  if (frd.empty()) GTEST_SKIP() << "../shared/data is not beside the project";
  auto input = open_input(std::vector<std::string>{frd});
  ASSERT_TRUE(input) << input.message();
  const std::vector<std::string> names = input->frames->field_names();
  for (double ratio : {0.05, 0.25}) {
    SimplifyOptions options;
    options.target_ratio = ratio;
    Trace geometry(input->topology.vertex_count), added(input->topology.vertex_count),
        scaled(input->topology.vertex_count);
    options.field_weight = 0;
    ASSERT_TRUE(simplify(input->topology, *input->frames, options, &geometry));
    options.field_weight = kDefaultFieldWeight;
    ASSERT_TRUE(simplify(input->topology, *input->frames, options, &scaled));
    options.field_weight = 0.01, options.field_combine = FieldCombine::kAdd;
    ASSERT_TRUE(simplify(input->topology, *input->frames, options, &added));
    for (const char* name : {"S_MISES", "PEEQ"}) {
      const auto it = std::find(names.begin(), names.end(), name);
      ASSERT_NE(it, names.end()) << name;
      const size_t f = size_t(it - names.begin());
      const double before = field_error(*input->frames, f, geometry);
      const double with_added = field_error(*input->frames, f, added);
      const double with_scaled = field_error(*input->frames, f, scaled);
      std::printf(
          "ratio %.2f %-8s field error %.1f %% geometry only, %.1f %% added, %.1f %% scaled\n",
          ratio, name, 100 * before, 100 * with_added, 100 * with_scaled);
      EXPECT_LE(with_added, 0.75 * before) << name << " at " << ratio;
      // The jump allowance (docs/simplify.md): without it the scaled cost merged flat walls
      // across the plastic hinges first (PEEQ at 5 %: 0.92 × the geometry-only error; S_MISES
      // 1.00). Measured with it: PEEQ 0.51 / 0.23, S_MISES 0.76 / 0.76 at 5 % / 25 %.
      EXPECT_LE(with_scaled, (std::string(name) == "PEEQ" ? 0.6 : 0.85) * before)
          << name << " at " << ratio;
    }
  }
}

// A flat plate whose left half holds 1 and right half 0, per face: with the field in the cost
// the line between them stays a line of vertices, and no face of the result spans it.
TEST(SimplifyFields, AnElementFieldsEdgeSurvives) {
  const test::Mesh plate = test::quad_grid(20, 20);
  const Animation a = plate.animation();
  std::vector<float> eps;
  for (const Face& face : a.topology.faces)
    eps.push_back(a.frames.step(0)[size_t{face.v[0]} * 3] < 10 ? 1.0f : 0.0f);
  const WithField frames(a.frames, eps);
  auto faces_across = [&](double weight) {
    SimplifyOptions options;
    options.target_ratio = 0.3;
    options.field_weight = weight;
    options.check_every_collapse = true;
    auto r = simplify(a.topology, frames, options);
    EXPECT_TRUE(r) << r.message();
    int across = 0;
    for (const Face& face : r->topology.faces) {
      bool left = false, right = false;
      for (int c = 0; c < face.degree(); ++c) {
        const float x = a.frames.step(0)[size_t{r->original_vertex[face.v[c]]} * 3];
        left |= x<10, right |= x> 10;
      }
      across += left && right;
    }
    return across;
  };
  EXPECT_EQ(faces_across(kDefaultFieldWeight), 0);
  EXPECT_GT(faces_across(0), 0);  // the geometry alone does not see the line
}

// On a flat plate a field linear in x and y is what every face's fit of the attribute quadric
// holds exactly: the quadric forms cost it nothing (up to the floats' rounding), the spread
// form costs every collapse the change of the value along it.
TEST(SimplifyFields, ALinearNodeFieldCostsNothingInTheAttributeQuadrics) {
  const test::Mesh plate = test::quad_grid(12, 12);
  const Animation a = plate.animation();
  std::vector<float> temp;
  for (uint32_t v = 0; v < a.topology.vertex_count; ++v)
    temp.push_back(2 * a.frames.step(0)[size_t{v} * 3] + 3 * a.frames.step(0)[size_t{v} * 3 + 1] +
                   5);
  const WithField frames(a.frames, temp, FieldLocation::kNode);
  auto worst_error = [&](FieldForm form) {
    SimplifyOptions options;
    options.target_ratio = 0.3;
    options.field_weight = 1;
    options.field_form = form;
    options.field_combine = FieldCombine::kAdd;  // the field term itself, in diagonals
    options.check_every_collapse = true;
    auto r = simplify(a.topology, frames, options);
    EXPECT_TRUE(r) << r.message();
    return r ? r->max_error : HUGE_VAL;
  };
  EXPECT_LT(worst_error(FieldForm::kAttributes), 0.005);
  EXPECT_LT(worst_error(FieldForm::kQuadric), 0.005);
  EXPECT_GT(worst_error(FieldForm::kSpread), 0.03);  // a spread of 3 % of the range at least
}

// The lasso d3plot plate is flat, the geometry alone reaches 5 % of the vertices with no
// distance to speak of, and its node field |V| varies everywhere. Added to the geometric
// error, the field term outbids it and the simplifier cuts the plate's outline; scaling each
// collapse's own geometric error keeps the outline (Hausdorff within 10 % of the geometry-only
// build's) and still lowers the field error to under 0.75 × the geometry-only one.
TEST(SimplifyFields, ScalingTheGeometricErrorKeepsAFlatPlatesOutline) {
  const std::string file =
      test::shared_data() + "/external/d3plot/lasso_d3plot_node_temperature_d3plot";
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "../shared/data is not beside the project";
  auto input = open_input(std::vector<std::string>{file});
  ASSERT_TRUE(input) << input.message();
  const Topology& topology = input->topology;
  const FrameSource& frames = *input->frames;
  std::vector<float> original(size_t{frames.vertex_count()} * 3), level;
  auto measure = [&](double weight, FieldCombine combine) {
    SimplifyOptions options;
    options.target_ratio = 0.05;
    options.field_weight = weight;
    options.field_combine = combine;
    Trace trace(topology.vertex_count);
    auto r = simplify(topology, frames, options, &trace);
    EXPECT_TRUE(r) << r.message();
    double distance = 0;
    for (size_t t : {size_t{0}, frames.step_count() / 2, frames.step_count() - 1}) {
      EXPECT_TRUE(frames.read_step(t, original).ok());
      level.clear();
      for (uint32_t v : r->original_vertex)
        level.insert(level.end(), &original[size_t{v} * 3], &original[size_t{v} * 3] + 3);
      auto h = hausdorff(topology, original, r->topology, level);
      EXPECT_TRUE(h) << h.message();
      distance = std::max(distance, h->hausdorff / h->diagonal);
    }
    return std::pair{distance, field_error(frames, 0, trace)};
  };
  const auto [geometry, geometry_field] = measure(0, FieldCombine::kAdd);
  const auto [added, added_field] = measure(0.01, FieldCombine::kAdd);
  const auto [scaled, scaled_field] = measure(kDefaultFieldWeight, FieldCombine::kScale);
  std::printf(
      "lasso plate at 5 %%: Hausdorff %.2g / %.2g / %.2g of the diagonal, field error "
      "%.1f / %.1f / %.1f %% (geometry only / added / scaled)\n",
      geometry, added, scaled, 100 * geometry_field, 100 * added_field, 100 * scaled_field);
  EXPECT_GT(added, 100 * geometry + 1e-4);
  EXPECT_LE(scaled, 1.1 * geometry + 1e-7);
  EXPECT_LE(scaled_field, 0.75 * geometry_field);
}

TEST(SimplifyFields, UnknownFieldIsRefusedNamingTheOthers) {
  test::TempDir dir;
  const std::string frd = crashbox_fields(dir);
  if (frd.empty()) GTEST_SKIP() << "../shared/data is not beside the project";
  auto input = open_input(std::vector<std::string>{frd});
  ASSERT_TRUE(input);
  SimplifyOptions options;
  options.field_weights = {{"PEEQ", 2.0}, {"STRAIN", std::nullopt}};
  auto chosen = cost_fields(options, *input->frames);
  ASSERT_FALSE(chosen);
  EXPECT_NE(chosen.message().find("'STRAIN'"), std::string::npos) << chosen.message();
  EXPECT_NE(chosen.message().find("S_MISES, PEEQ"), std::string::npos) << chosen.message();
  EXPECT_FALSE(simplify(input->topology, *input->frames, options));
  options.field_weights = {{"PEEQ", 2.0}};
  chosen = cost_fields(options, *input->frames);
  ASSERT_TRUE(chosen);
  ASSERT_EQ(chosen->size(), 1u);
  EXPECT_EQ((*chosen)[0].weight, 2.0);

  const auto usage =
      test::run_command(std::string(DYNPM_CLI) + " simplify '" + frd + "' -o '" +
                        dir.file("out_{:03d}.obj") + "' --ratio 0.5 --field STRAIN:2 2>&1");
  EXPECT_EQ(usage.exit_code, 2) << usage.output;
  EXPECT_NE(usage.output.find("unknown field 'STRAIN'"), std::string::npos) << usage.output;
  EXPECT_NE(usage.output.find("PEEQ"), std::string::npos) << usage.output;
}

// Triangle aspect ratio: longest edge × perimeter / (4√3 · area); 1 for an equilateral one.
double aspect(const float* a, const float* b, const float* c) {
  auto d = [](const float* p, const float* q) {
    return std::hypot(double{p[0]} - q[0], double{p[1]} - q[1], double{p[2]} - q[2]);
  };
  const double ab = d(a, b), bc = d(b, c), ca = d(c, a), s = (ab + bc + ca) / 2;
  const double area = std::sqrt(std::max(0.0, s * (s - ab) * (s - bc) * (s - ca)));
  return area > 0 ? std::max({ab, bc, ca}) * 2 * s / (4 * std::sqrt(3.0) * area) : HUGE_VAL;
}

TEST(SimplifyFields, RegularizerKeepsAFlatPlateWellShaped) {
  const test::Mesh plate = test::quad_grid(40, 40);
  const Animation a = plate.animation();
  auto worst_aspects = [&](double regularize) {
    SimplifyOptions options;
    options.target_ratio = 0.05;
    options.regularize = regularize;
    auto r = simplify(a.topology, a.frames, options);
    EXPECT_TRUE(r) << r.message();
    std::vector<double> aspects;
    for (const Face& face : r->topology.faces) {
      if (!face.is_triangle()) continue;
      auto p = [&](int c) { return &a.frames.step(0)[size_t{r->original_vertex[face.v[c]]} * 3]; };
      aspects.push_back(aspect(p(0), p(1), p(2)));
    }
    std::sort(aspects.begin(), aspects.end());
    return aspects.empty() ? 1.0 : aspects[aspects.size() * 9 / 10];  // the 90th percentile
  };
  const double off = worst_aspects(0), on = worst_aspects(0.001);
  std::printf("flat 40 x 40 plate at 5 %%: 90th-percentile aspect %.2f without, %.2f with\n", off,
              on);
  EXPECT_LT(on, 0.5 * off);
}

}  // namespace
}  // namespace dynpm
