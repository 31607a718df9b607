// Which point of the other surface a sample's field value is compared with (docs/eval.md,
// "Facing correspondence"): where a fold's sheets touch, the closest point may lie on the other
// sheet, which faces the other way. Checked on a synthetic fold (two plates, opposite normals,
// different values); and the per-node measure against the navigator's own ancestors on the
// built CalculiX crash box.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>

#include "dynpm/io.h"
#include "dynpm/lod.h"
#include "dynpm/pipeline.h"
#include "fixtures.h"
#include "third_party.h"

namespace dynpm {
namespace {

struct Prepared {
  SurfaceTopology topology;
  Surface surface;
};

// On the heap: the surface points to its topology.
std::unique_ptr<Prepared> prepare(const Topology& topology, std::span<const float> positions) {
  auto p = std::make_unique<Prepared>();
  auto t = prepare_topology("mesh", topology);
  EXPECT_TRUE(t.ok()) << t.message();
  p->topology = std::move(t).value();
  auto s = prepare_surface("mesh", p->topology, positions, 1);
  EXPECT_TRUE(s.ok()) << s.message();
  p->surface = std::move(s).value();
  return p;
}

// A sheet folded onto itself: a 6 × 6 plate at z = −shift facing up and carrying 0, and above
// it, 0.01 higher, the same plate facing down carrying 1 (test::two_sheets).
test::Mesh folded_sheets(float shift, std::vector<float>& values) {
  test::Mesh plate = test::quad_grid(4, 4);
  for (size_t v = 0; v < plate.positions.size(); v += 3)
    plate.positions[v] *= 1.5f, plate.positions[v + 1] *= 1.5f;
  return test::two_sheets(std::move(plate), shift, true, values);
}

// Shifted by 0.006, each sheet of B lies nearer A's other sheet (0.004) than its own (0.006):
// the closest point reads the other sheet's value, an error of 1 that is the measure's, not
// B's. Facing, a sample finds its own sheet 0.002 farther than the closest point: the error is
// 0 within that reach, 1 (the closest point, as a fallback) when the reach is shorter, and a
// real difference (0.5 on B's lower sheet) is still seen.
TEST(FieldMatch, AFacingMatchDoesNotMixTheSheetsOfAFold) {
  std::vector<float> fa, fb;
  const test::Mesh a_mesh = folded_sheets(0, fa), b_mesh = folded_sheets(0.006f, fb);
  const auto a = prepare(a_mesh.topology, a_mesh.positions);
  const auto b = prepare(b_mesh.topology, b_mesh.positions);
  auto measure = [&](double reach, const std::vector<float>& b_values) {
    HausdorffOptions options;
    options.threads = 1;
    options.field_facing_reach = reach;
    const FieldPair pair{{FieldLocation::kNode, fa}, {FieldLocation::kNode, b_values}};
    auto r = hausdorff(a->surface, b->surface, options, {&pair, 1});
    EXPECT_TRUE(r.ok()) << r.message();
    return r->fields.at(0);
  };
  const FieldDistance nearest = measure(0, fb);
  EXPECT_NEAR(nearest.max, 1, 1e-6);
  EXPECT_EQ(nearest.max, nearest.nearest);  // without a reach the two are one measure
  const FieldDistance facing = measure(0.01, fb);
  EXPECT_NEAR(facing.max, 0, 1e-6);
  EXPECT_NEAR(facing.a_to_b, 0, 1e-6);
  EXPECT_NEAR(facing.b_to_a, 0, 1e-6);
  EXPECT_NEAR(facing.nearest, 1, 1e-6);  // the old measure, reported beside
  // The mean over the area samples: half of them land on the wrong sheet by the closest point.
  EXPECT_NEAR(facing.mean, 0, 1e-6);
  EXPECT_GT(nearest.mean, 0.3);
  EXPECT_LT(nearest.mean, 0.7);
  EXPECT_NEAR(measure(0.0015, fb).max, 1, 1e-6);
  std::vector<float> lower_half = fb;  // B's lower sheet reads 0.5: a real error of 0.5
  std::fill(lower_half.begin(), lower_half.begin() + lower_half.size() / 2, 0.5f);
  EXPECT_NEAR(measure(0.01, lower_half).max, 0.5, 1e-6);
}

// Sheets of one orientation (a stack, not a fold) cannot be told apart by facing: the closest
// point stays the match, so the measure is the old one.
TEST(FieldMatch, SheetsFacingTheSameWayKeepTheClosestPoint) {
  std::vector<float> fa, fb;
  test::Mesh a_mesh = folded_sheets(0, fa), b_mesh = folded_sheets(0.006f, fb);
  for (test::Mesh* m : {&a_mesh, &b_mesh})  // the upper sheet faces up again
    for (size_t f = m->topology.faces.size() / 2; f < m->topology.faces.size(); ++f) {
      Face& face = m->topology.faces[f];
      std::reverse(face.v.begin(), face.v.begin() + face.degree());
    }
  const auto a = prepare(a_mesh.topology, a_mesh.positions);
  const auto b = prepare(b_mesh.topology, b_mesh.positions);
  HausdorffOptions options;
  options.threads = 1;
  options.field_facing_reach = 0.01;
  const FieldPair pair{{FieldLocation::kNode, fa}, {FieldLocation::kNode, fb}};
  auto r = hausdorff(a->surface, b->surface, options, {&pair, 1});
  ASSERT_TRUE(r.ok()) << r.message();
  EXPECT_NEAR(r->fields[0].max, 1, 1e-6);
  EXPECT_EQ(r->fields[0].max, r->fields[0].nearest);
}

// Two plates crossing at right angles (sharing no vertex) pass through each other along one
// line: the faces of each plate along that line cross, no other face does; the folded sheets
// (parallel, 0.01 apart) and a plate bent along a row of edges (its faces meet at shared
// vertices) do not cross.
TEST(FieldMatch, SelfCrossingFacesAreWhereSheetsPassThroughEachOther) {
  // A: the 4 × 4 grid on z = 0; B: the same grid turned upright, (x, y) → (2.5, y + 0.4, x − 2.4).
  // They cross along x = 2.5, z = 0, y ∈ [0.4, 4]: A's column of quads x ∈ [2, 3] (4 faces)
  // and B's column from z = −0.4 to 0.6 (4 faces). No corner or edge lies on the other plate.
  const test::Mesh plate = test::quad_grid(4, 4);
  const uint32_t n = plate.topology.vertex_count;
  test::Mesh mesh;
  mesh.topology = Topology::with_vertices(2 * n);
  mesh.positions = plate.positions;
  for (size_t v = 0; v < plate.positions.size(); v += 3)
    mesh.positions.insert(mesh.positions.end(),
                          {2.5f, plate.positions[v + 1] + 0.4f, plate.positions[v] - 2.4f});
  for (uint32_t offset : {0u, n})
    for (const Face& f : plate.topology.faces)
      mesh.topology.add_quad(f.v[0] + offset, f.v[1] + offset, f.v[2] + offset, f.v[3] + offset, 0);
  const std::vector<uint32_t> faces =
      self_crossing_faces(prepare(mesh.topology, mesh.positions)->surface);
  EXPECT_EQ(faces.size(), 8u);
  for (uint32_t f : faces) {
    double x = 0, z = 0;
    for (uint32_t v : mesh.topology.faces[f].v) {
      x += mesh.positions[3 * v] / 4;
      z += mesh.positions[3 * v + 2] / 4;
    }
    if (f < plate.topology.faces.size())
      EXPECT_NEAR(x, 2.5, 1e-6) << f;
    else
      EXPECT_NEAR(z, 0.1, 1e-6) << f;
  }
  std::vector<float> values;
  const test::Mesh fold = folded_sheets(0, values);
  EXPECT_TRUE(self_crossing_faces(prepare(fold.topology, fold.positions)->surface).empty());
  test::Mesh bent = test::quad_grid(4, 4);
  for (size_t v = 0; v < bent.positions.size(); v += 3)
    if (bent.positions[v] > 2) bent.positions[v + 2] = 2 * (bent.positions[v] - 2);
  EXPECT_TRUE(self_crossing_faces(prepare(bent.topology, bent.positions)->surface).empty());
}

// The per-node measure: each original node against the value its representative shows, the
// representative found here by Navigator::ancestor and the input's order by original_order(),
// on the crash box built lossless. At full resolution every node is its own representative.
TEST(FieldMatch, TheNodeMeasureComparesEachNodeWithItsRepresentative) {
  test::TempDir dir;
  const std::string frd = dir.file("box.frd"), dpm = dir.file("box.dpm");
  const std::string gz = test::shared_data() + "/crashbox-fields/crashbox-fields.frd.gz";
  if (std::system(("zcat '" + gz + "' > '" + frd + "' 2>/dev/null").c_str()) != 0)
    GTEST_SKIP() << "../shared/data/crashbox-fields is missing";
  const auto build = test::run_command(std::string(DYNPM_CLI) + " build --lossless '" + frd +
                                       "' -o '" + dpm + "'");
  ASSERT_EQ(build.exit_code, 0) << build.output;
  auto model = read_dpm(dpm);
  ASSERT_TRUE(model.ok()) << model.message();
  auto stream = open_input(std::vector<std::string>{frd});
  ASSERT_TRUE(stream.ok()) << stream.message();
  LevelsOptions options;
  options.ratios = {5, 100};
  options.steps = {12, 13};
  options.max_over_all_steps = false;
  options.fields = {"PEEQ"};
  options.hausdorff.threads = 2;
  options.hausdorff.samples_per_face = 1;
  auto table = evaluate_levels(stream->topology, *stream->frames, *model, options);
  ASSERT_TRUE(table.ok()) << table.message();

  Navigator nav(*model);
  nav.set_level(model->split_count());
  auto order = original_order(nav);
  ASSERT_TRUE(order.ok()) << order.message();
  size_t peeq = 0;
  while (model->fields[peeq].info.name != "PEEQ") ++peeq;
  std::vector<float> original(model->full_vertex_count);
  ASSERT_TRUE(stream->frames
                  ->read_field(
                      [&] {
                        const auto fields = stream->frames->fields();
                        size_t i = 0;
                        while (fields[i].name != "PEEQ") ++i;
                        return i;
                      }(),
                      13, original)
                  .ok());
  ASSERT_EQ(table->crossings.size(), 1u);
  EXPECT_EQ(table->crossings[0].first, 13u);
  EXPECT_EQ(table->crossings[0].second, 105u);
  for (const LevelRow& row : table->rows) {
    nav.set_level(row.level);
    std::vector<float> shown(nav.vertex_count());
    nav.field_values(peeq, 13, shown);
    double largest = 0;
    for (uint32_t i = 0; i < model->full_vertex_count; ++i) {
      const uint32_t v = order->vertex_of_original[i];
      largest =
          std::max(largest, std::abs(double(original[i]) - shown[nav.ancestor(v, row.level)]));
    }
    const double pct = 100 * largest / table->field_ranges[0];
    EXPECT_NEAR(row.steps[1].field_error_node_pct[0], pct, 1e-9) << row.ratio;
    // The crushed box passes through itself at step 13, not 12 (the run has no contact; the
    // face count is scripts/self_intersections.py's, an independent check in Python): step 13's
    // field error is reported as such and left out of the untangled max.
    EXPECT_EQ(row.steps[0].field_error_untangled_pct[0], row.steps[0].field_error_pct[0]);
    EXPECT_TRUE(std::isnan(row.steps[1].field_error_untangled_pct[0]));
    EXPECT_EQ(row.max.field_error_untangled_pct[0], row.steps[0].field_error_pct[0]);
    if (row.ratio == 100)
      EXPECT_EQ(pct, 0);
    else
      EXPECT_GT(pct, 1) << "a coarse level's clusters mix strains";
  }
}

}  // namespace
}  // namespace dynpm
