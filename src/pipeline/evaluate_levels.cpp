// evaluate_levels(): the paper's Table 2, a progressive mesh measured against the animation it
// was built from (dynpm/pipeline.h has the loop as pseudocode).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "dynpm/lod.h"
#include "dynpm/pipeline.h"

namespace dynpm {

Status check_built_from(const Topology& original, const FrameSource& frames,
                        const ProgressiveMesh& model, const std::string& model_name) {
  if (model.full_vertex_count != original.vertex_count ||
      model.full_face_count != original.faces.size())
    return Status::error(model_name + " was built from another mesh: it has " +
                         std::to_string(model.full_vertex_count) + " vertices and " +
                         std::to_string(model.full_face_count) + " faces, the original " +
                         std::to_string(original.vertex_count) + " vertices and " +
                         std::to_string(original.faces.size()) + " faces");
  if (model.step_count() != frames.step_count())
    return Status::error(model_name + " was built from another animation: it has " +
                         std::to_string(model.step_count()) + " time steps, the original " +
                         std::to_string(frames.step_count()));
  return {};
}

Result<LevelsTable> evaluate_levels(const Topology& original, const FrameSource& frames,
                                    const ProgressiveMesh& model, const LevelsOptions& options) {
  DYNPM_RETURN_IF_ERROR(check_built_from(original, frames, model, options.model_name));
  const size_t steps = frames.step_count();
  if (steps == 0) return Status::error("the original has no time steps");
  LevelsTable table;
  HausdorffOptions h = options.hausdorff;
  if (h.reference_diagonal == 0) h.reference_diagonal = model.diagonal();
  table.reference_diagonal = h.reference_diagonal;

  // The columns: as given, or the first, middle and last step.
  table.steps = options.steps;
  if (table.steps.empty()) table.steps = {0, (steps - 1) / 2, steps - 1};
  std::sort(table.steps.begin(), table.steps.end());
  table.steps.erase(std::unique(table.steps.begin(), table.steps.end()), table.steps.end());
  if (table.steps.back() > steps - 1)
    return Status::error("step " + std::to_string(table.steps.back()) + " is past the last step, " +
                         std::to_string(steps - 1));

  // One row per ratio, with the level's faces kept as a Topology. Positions need no level:
  // vertex v has the same position at every level where it exists, so the finest level's
  // positions serve every row (a prefix of them).
  std::vector<double> ratios = options.ratios;
  std::sort(ratios.begin(), ratios.end());
  ratios.erase(std::unique(ratios.begin(), ratios.end()), ratios.end());
  Navigator nav(model);
  std::vector<Topology> level_faces;
  for (double ratio : ratios) {
    const double wanted = std::round(ratio / 100.0 * model.full_vertex_count);
    nav.set_vertex_count(static_cast<uint32_t>(std::max(1.0, wanted)));
    LevelRow row;
    row.ratio = ratio;
    row.vertices = nav.vertex_count();
    row.faces = nav.face_count();
    row.level = nav.level();
    row.error = nav.error();
    row.steps.resize(table.steps.size());
    table.rows.push_back(std::move(row));
    level_faces.push_back(nav.topology());
  }
  nav.set_level(model.split_count());

  std::vector<size_t> measured;  // the steps of the max column
  if (options.max_over_all_steps)
    for (size_t t = 0; t < steps; ++t) measured.push_back(t);
  else
    measured = table.steps;
  std::vector<float> original_xyz(size_t{original.vertex_count} * 3);
  std::vector<float> model_xyz(size_t{nav.vertex_count()} * 3);
  for (size_t k = 0; k < measured.size(); ++k) {
    const size_t t = measured[k];
    if (options.progress) options.progress(k, measured.size());
    DYNPM_RETURN_IF_ERROR(frames.read_step(t, original_xyz));
    nav.positions(double(t), model_xyz);
    const auto column = std::find(table.steps.begin(), table.steps.end(), t);
    for (size_t i = 0; i < table.rows.size(); ++i) {
      LevelRow& row = table.rows[i];
      const std::span<const float> xyz(model_xyz.data(), size_t{row.vertices} * 3);
      auto r = hausdorff(original, original_xyz, level_faces[i], xyz, h);
      if (!r)
        return Status::error("step " + std::to_string(t) + ", " + std::to_string(row.vertices) +
                             " vertices: " + r.message());
      const LevelDistance cell{r->percent(r->hausdorff), r->percent(r->mean), r->percent(r->rms),
                               r->diagonal};
      if (column != table.steps.end()) row.steps[size_t(column - table.steps.begin())] = cell;
      if (k == 0 || cell.hausdorff_pct > row.max.hausdorff_pct) {
        row.max.hausdorff_pct = cell.hausdorff_pct;
        row.max.diagonal = cell.diagonal;
        row.max_step = t;
      }
      row.max.mean_pct = std::max(row.max.mean_pct, cell.mean_pct);
      row.max.rms_pct = std::max(row.max.rms_pct, cell.rms_pct);
    }
  }
  if (options.progress) options.progress(measured.size(), measured.size());
  return table;
}

}  // namespace dynpm
