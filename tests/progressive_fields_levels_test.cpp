// Result fields at every level of detail (docs/FORMAT.md, "Shown values" and "Field errors"): on
// a real CalculiX run the largest |value| shown at any level and step is the original's largest
// (within the quantization bound), for node and element fields; the mean aggregate keeps the
// mean; field errors never increase and are the largest spread a level shows; on random meshes
// Navigator::field_values() equals a brute force that walks each original vertex (face) to what
// stands for it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "dynpm/io.h"
#include "dynpm/lod.h"
#include "dynpm/pipeline.h"
#include "field_sources.h"
#include "fixtures.h"
#include "random_meshes.h"
#include "round_trip.h"
#include "third_party.h"

namespace dynpm {
namespace {

using namespace test;

// What item i (a vertex, or a face of an element field) is shown by at level k: its ancestor,
// or the end of its chain of heirs.
uint32_t standing_for(const Navigator& nav, const ProgressiveField& f, uint32_t i, uint32_t k) {
  const ProgressiveMesh& m = nav.mesh();
  if (f.info.location == FieldLocation::kNode) return nav.ancestor(i, k);
  const uint32_t faces = m.face_count_after(k);
  while (i >= faces) i = m.face_heir[i];
  return i;
}

float larger_magnitude(float a, float b) {
  return std::abs(a) > std::abs(b) || (std::abs(a) == std::abs(b) && a >= b) ? a : b;
}

// The brute force of FORMAT.md's "Shown values" at level k and step t: for each present item, the
// max-|value| and the mean of the values it stands for, and the spread (max − min) of them.
struct Brute {
  std::vector<float> max_abs;
  std::vector<double> mean;
  double spread = 0;
};
Brute brute_force(const Navigator& nav, const ProgressiveField& f, size_t t, uint32_t k) {
  const std::vector<float>& values = f.values[t];
  const bool per_face = f.info.location == FieldLocation::kElement;
  const uint32_t shown =
      per_face ? nav.mesh().face_count_after(k) : nav.mesh().base_vertex_count + k;
  Brute b;
  b.max_abs.assign(values.begin(), values.begin() + shown);
  std::vector<double> sum(values.begin(), values.begin() + shown), lo(sum), hi(sum);
  std::vector<uint32_t> count(shown, 1);
  for (uint32_t i = shown; i < values.size(); ++i) {
    const uint32_t s = standing_for(nav, f, i, k);
    b.max_abs[s] = larger_magnitude(b.max_abs[s], values[i]);
    sum[s] += values[i];
    ++count[s];
    lo[s] = std::min<double>(lo[s], values[i]);
    hi[s] = std::max<double>(hi[s], values[i]);
  }
  b.mean.resize(shown);
  for (uint32_t s = 0; s < shown; ++s) {
    b.mean[s] = sum[s] / count[s];
    b.spread = std::max(b.spread, hi[s] - lo[s]);
  }
  return b;
}

TEST(ProgressiveFieldLevels, PeaksAreNeverHiddenOnACalculixRun) {
  const std::string gz = shared_data() + "/crashbox-fields/crashbox-fields.frd.gz";
  if (!std::filesystem::exists(gz)) GTEST_SKIP() << gz << " is missing";
  const TempDir dir;
  const std::string frd = dir.file("crashbox-fields.frd");
  ASSERT_EQ(run_command("gzip -dc '" + gz + "' > '" + frd + "'").exit_code, 0);
  auto stream = open_input(std::vector<std::string>{frd});
  ASSERT_TRUE(stream.ok()) << stream.message();
  const FrameSource& frd_frames = *stream->frames;
  const std::vector<std::string> names = frd_frames.field_names();
  const auto peeq = std::find(names.begin(), names.end(), "PEEQ") - names.begin();
  ASSERT_LT(size_t(peeq), names.size());
  ASSERT_NE(std::find(names.begin(), names.end(), "S_MISES"), names.end());
  WithFields source(frd_frames, stream->topology);
  source.add_element_mean("PEEQ_elem", size_t(peeq));
  auto built = build_progressive_mesh(stream->topology, source, BuildOptions{});
  ASSERT_TRUE(built.ok()) << built.message();
  const ProgressiveMesh pm = through_file(*built);
  Navigator nav(pm);
  const uint32_t n = pm.full_vertex_count, b = pm.base_vertex_count;
  for (const uint32_t vertices : {b, std::max(b, n / 20), std::max(b, n / 4), n}) {
    nav.set_vertex_count(vertices);
    const uint32_t k = nav.level();
    for (size_t f = 0; f < pm.fields.size(); ++f) {
      const ProgressiveField& field = pm.fields[f];
      SCOPED_TRACE(field.info.name + " at " + std::to_string(vertices) + " vertices");
      const bool per_face = field.info.location == FieldLocation::kElement;
      std::vector<float> input(per_face ? stream->topology.faces.size() : n);
      std::vector<float> shown(input.size()), mean(input.size());
      const uint32_t present = per_face ? nav.face_count() : nav.vertex_count();
      for (size_t t = 0; t < pm.step_count(); ++t) {
        ASSERT_TRUE(source.read_field(f, t, input).ok());
        double peak = 0;
        for (float x : input) peak = std::max<double>(peak, std::abs(x));
        nav.field_values(f, t, shown);
        double peak_shown = 0;
        for (uint32_t i = 0; i < present; ++i)
          peak_shown = std::max<double>(peak_shown, std::abs(shown[i]));
        ASSERT_NEAR(peak_shown, peak, field.max_error * (1 + 1e-6)) << "step " << t;
        // The mean aggregate, weighted by how many each present item stands for, is the mean.
        nav.field_values(f, t, mean, FieldAggregate::kMean);
        std::vector<uint32_t> count(present, 0);
        for (uint32_t i = 0; i < field.values[t].size(); ++i)
          ++count[standing_for(nav, field, i, k)];
        double weighted = 0, all = 0, magnitude = 0;
        for (uint32_t i = 0; i < present; ++i) weighted += double(mean[i]) * count[i];
        for (float x : field.values[t]) all += x, magnitude += std::abs(x);
        ASSERT_NEAR(weighted, all, 1e-6 * magnitude + 1e-30) << "step " << t;
      }
      // The level's field error bounds every spread it shows, and is one of them.
      double spread = 0;
      for (size_t t = 0; t < pm.step_count(); ++t)
        spread = std::max(spread, brute_force(nav, field, t, k).spread);
      const double range = field.max - field.min;
      EXPECT_NEAR(nav.field_error(f), spread / range, 2 * field.max_error / range + 1e-6);
    }
  }
  EXPECT_GT(pm.fields[0].base_error, 0.1f);  // the base mesh does merge different values
}

// Deterministic values of either sign with zeros, from the position and the step.
float noisy(const float* p, size_t t) {
  const float x = std::sin(12.9898f * p[0] + 78.233f * p[1] + 3.1f * p[2] + 0.7f * float(t));
  return std::abs(x) < 0.3f ? 0.0f : x * 100.0f;
}

TEST(PropertyProgressiveFields, ShownValuesAndErrorsAreTheBruteForces) {
  for (uint32_t seed : seeds(4000, 8)) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Rng rng(seed);
    const RandomCase c = random_case(rng, 1500);
    SCOPED_TRACE(c.description);
    const Animation& a = c.animation;
    WithFields source(a.frames, a.topology);
    source.add_node_field("noise", noisy);
    source.add_element_mean("noise_elem", 0);
    BuildOptions o = random_build_options(rng, a);
    auto built = build_progressive_mesh(a.topology, source, o);
    ASSERT_TRUE(built.ok()) << built.message();
    const ProgressiveMesh pm = through_file(*built);
    Navigator nav(pm);
    std::vector<float> shown(std::max(pm.full_vertex_count, pm.full_face_count));
    for (int round = 0; round < 6; ++round) {
      const uint32_t k = round == 0   ? 0
                         : round == 1 ? pm.split_count()
                                      : pick(rng, 0, pm.split_count());
      nav.set_level(k);
      for (size_t f = 0; f < 2; ++f) {
        const ProgressiveField& field = pm.fields[f];
        SCOPED_TRACE(field.info.name + " at level " + std::to_string(k));
        double spread = 0;
        for (size_t t = 0; t < pm.step_count(); ++t) {
          const Brute brute = brute_force(nav, field, t, k);
          spread = std::max(spread, brute.spread);
          nav.field_values(f, t, shown);
          for (size_t i = 0; i < brute.max_abs.size(); ++i)
            ASSERT_EQ(shown[i], brute.max_abs[i]) << "item " << i << " step " << t;
          nav.field_values(f, t, shown, FieldAggregate::kMean);
          for (size_t i = 0; i < brute.mean.size(); ++i)
            ASSERT_NEAR(shown[i], brute.mean[i], 1e-4 * (1 + std::abs(brute.mean[i])))
                << "item " << i << " step " << t;
        }
        // Exact when lossless; the quantization moves a spread by at most two bounds.
        const double range = field.max - field.min;
        const double slack = o.lossless ? 0 : 2 * field.max_error / range;
        EXPECT_NEAR(nav.field_error(f), spread / range, slack + 1e-6);
      }
    }
    for (const ProgressiveField& field : pm.fields)
      for (uint32_t i = 0; i < pm.split_count(); ++i)
        ASSERT_LE(field.error[i], i == 0 ? field.base_error : field.error[i - 1]);
  }
}

}  // namespace
}  // namespace dynpm
