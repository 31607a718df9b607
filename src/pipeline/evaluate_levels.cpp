// evaluate_levels(): the paper's Table 2, a progressive mesh measured against the animation it
// was built from (dynpm/pipeline.h has the loop as pseudocode).
#include <algorithm>
#include <cmath>
#include <limits>
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

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Each vertex of the full mesh → the vertex that stands for it at the navigator's level (itself
// if present). A parent is created before its children, so one pass in vertex order does.
std::vector<uint32_t> representatives_at(const Navigator& nav) {
  const ProgressiveMesh& m = nav.mesh();
  const uint32_t b = m.base_vertex_count, present = nav.vertex_count();
  std::vector<uint32_t> rep(m.full_vertex_count);
  for (uint32_t v = 0; v < m.full_vertex_count; ++v)
    rep[v] = v < present ? v : rep[m.parent[v - b]];
  return rep;
}

// The largest |original value − the value its representative shows| over the original's nodes.
double node_error(const ProgressiveMesh& m, std::span<const uint32_t> representative,
                  std::span<const float> original, std::span<const float> shown) {
  double error = 0;
  for (uint32_t v = 0; v < representative.size(); ++v) {
    const uint32_t input = m.vertex_original_index.empty() ? v : m.vertex_original_index[v];
    error = std::max(error, std::abs(double(original[input]) - shown[representative[v]]));
  }
  return error;
}

}  // namespace

Result<LevelsTable> evaluate_levels(const Topology& original, const FrameSource& frames,
                                    const ProgressiveMesh& model, const LevelsOptions& options) {
  DYNPM_RETURN_IF_ERROR(check_built_from(original, frames, model, options.model_name));
  const size_t steps = frames.step_count();
  if (steps == 0) return Status::error("the original has no time steps");
  LevelsTable table;
  HausdorffOptions h = options.hausdorff;
  if (h.reference_diagonal == 0) h.reference_diagonal = model.diagonal();
  table.reference_diagonal = h.reference_diagonal;
  // Every stored position is within the model's bound of the original: where sheets touch, a
  // level's point that close to the closest one matches a sample as well (docs/eval.md).
  h.field_tolerance = std::max(h.field_tolerance, model.max_error);
  h.field_facing_reach = options.field_facing_reach_pct / 100 * h.reference_diagonal;

  // The columns: as given, or the first, middle and last step.
  table.steps = options.steps;
  if (table.steps.empty()) table.steps = {0, (steps - 1) / 2, steps - 1};
  std::sort(table.steps.begin(), table.steps.end());
  table.steps.erase(std::unique(table.steps.begin(), table.steps.end()), table.steps.end());
  if (table.steps.back() > steps - 1)
    return Status::error("step " + std::to_string(table.steps.back()) + " is past the last step, " +
                         std::to_string(steps - 1));

  // The fields: their index in the original's source and in the model, and their range.
  const std::vector<FieldInfo> source_fields = frames.fields();
  std::vector<size_t> source_index, model_index;
  for (const std::string& name : options.fields) {
    auto in_source = std::find_if(source_fields.begin(), source_fields.end(),
                                  [&](const FieldInfo& f) { return f.name == name; });
    auto in_model = std::find_if(model.fields.begin(), model.fields.end(),
                                 [&](const ProgressiveField& f) { return f.info.name == name; });
    if (in_source == source_fields.end())
      return Status::error("the original has no field '" + name + "'");
    if (in_model == model.fields.end())
      return Status::error(options.model_name + " has no field '" + name + "'");
    if (in_model->info.location != in_source->location)
      return Status::error("field '" + name + "' is per " + to_string(in_source->location) +
                           " in the original but per " + to_string(in_model->info.location) +
                           " in " + options.model_name);
    if (in_source->location == FieldLocation::kElement && model.face_heir.empty())
      return Status::error(options.model_name + " has no face heirs for the element field '" +
                           name + "'");
    source_index.push_back(size_t(in_source - source_fields.begin()));
    model_index.push_back(size_t(in_model - model.fields.begin()));
    table.field_ranges.push_back(in_model->max - in_model->min);
  }
  const size_t field_count = options.fields.size();

  // One row per ratio, with the level's faces kept as a Topology, checked and its edges listed
  // once for every step. Positions need no level: vertex v has the same position at every level
  // where it exists, so the finest level's positions serve every row (a prefix of them).
  std::vector<double> ratios = options.ratios;
  std::sort(ratios.begin(), ratios.end());
  ratios.erase(std::unique(ratios.begin(), ratios.end()), ratios.end());
  Navigator nav(model);
  std::vector<std::vector<uint32_t>> representatives;  // per row, with fields
  std::vector<Topology> level_faces;
  level_faces.reserve(ratios.size());  // the prepared topologies point into it
  std::vector<SurfaceTopology> level_surfaces;
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
    row.max.field_error_pct.assign(field_count, 0);
    row.max.peak_ratio.assign(field_count, std::numeric_limits<double>::infinity());
    row.max.peak_gap_pct.assign(field_count, -std::numeric_limits<double>::infinity());
    row.max.field_error_nearest_pct.assign(field_count, 0);
    row.max.field_error_node_pct.assign(field_count, 0);
    row.max.field_error_mean_pct.assign(field_count, 0);
    row.max.field_error_at.assign(field_count, Point3{0, 0, 0});
    row.max.field_error_untangled_pct.assign(field_count, kNaN);
    table.rows.push_back(std::move(row));
    level_faces.push_back(nav.topology());
    auto prepared = prepare_topology("the level", level_faces.back());
    if (!prepared)
      return Status::error(std::to_string(nav.vertex_count()) + " vertices: " + prepared.message());
    level_surfaces.push_back(std::move(prepared).value());
    if (field_count > 0) representatives.push_back(representatives_at(nav));
  }
  auto original_surface = prepare_topology("the original", original);
  if (!original_surface) return original_surface.status();

  std::vector<size_t> measured;  // the steps of the max column
  if (options.max_over_all_steps)
    for (size_t t = 0; t < steps; ++t) measured.push_back(t);
  else
    measured = table.steps;
  nav.set_level(model.split_count());
  std::vector<float> original_xyz(size_t{original.vertex_count} * 3);
  std::vector<float> model_xyz(size_t{nav.vertex_count()} * 3);
  std::vector<std::vector<float>> original_values(field_count), level_values(field_count);
  std::vector<double> original_peak(field_count);
  // Each surface at the current step, updated in place from step to step (its BVH refitted,
  // no memory allocated: at a million vertices the fresh pages cost as much as the builds).
  Surface original_step;
  original_step.topology = &*original_surface;
  // The levels' surfaces are kept between steps only while together they are no larger than
  // the original (a long list of ratios up to 100 % would otherwise hold many originals).
  std::vector<Surface> level_steps(table.rows.size());
  size_t level_faces_total = 0;
  for (size_t i = 0; i < level_steps.size(); ++i) {
    level_steps[i].topology = &level_surfaces[i];
    level_faces_total += table.rows[i].faces;
  }
  const bool keep_levels = level_faces_total <= original.faces.size();
  for (size_t k = 0; k < measured.size(); ++k) {
    const size_t t = measured[k];
    if (options.progress) options.progress(k, measured.size());
    DYNPM_RETURN_IF_ERROR(frames.read_step(t, original_xyz));
    nav.set_level(model.split_count());
    nav.positions(double(t), model_xyz);
    // The original's side of every measurement at this step, built once.
    const Status original_ready =
        update_surface("the original", original_step, original_xyz, h.threads);
    if (!original_ready.ok())
      return Status::error("step " + std::to_string(t) + ": " + original_ready.message());
    // Where the original's sheets pass through each other the field error measures the
    // crossing: found once per step, and the max over the other steps kept beside.
    bool untangled = true;
    if (field_count > 0) {
      const size_t crossing = self_crossing_faces(original_step).size();
      if (crossing > 0) table.crossings.push_back({t, uint32_t(crossing)}), untangled = false;
    }
    for (size_t f = 0; f < field_count; ++f) {
      const bool per_face = source_fields[source_index[f]].location == FieldLocation::kElement;
      original_values[f].resize(per_face ? original.faces.size() : original.vertex_count);
      DYNPM_RETURN_IF_ERROR(frames.read_field(source_index[f], t, original_values[f]));
      original_peak[f] = 0;
      for (float v : original_values[f])
        original_peak[f] = std::max<double>(original_peak[f], std::abs(v));
    }
    const auto column = std::find(table.steps.begin(), table.steps.end(), t);
    for (size_t i = 0; i < table.rows.size(); ++i) {
      LevelRow& row = table.rows[i];
      const std::span<const float> xyz(model_xyz.data(), size_t{row.vertices} * 3);
      const std::string where =
          "step " + std::to_string(t) + ", " + std::to_string(row.vertices) + " vertices: ";
      const Status level_ready = update_surface("the level", level_steps[i], xyz, h.threads);
      if (!level_ready.ok()) return Status::error(where + level_ready.message());
      std::vector<FieldPair> pairs;
      LevelDistance cell;
      if (field_count > 0) nav.set_level(row.level);
      for (size_t f = 0; f < field_count; ++f) {
        const FieldLocation location = source_fields[source_index[f]].location;
        level_values[f].resize(location == FieldLocation::kElement ? row.faces : row.vertices);
        nav.field_values(model_index[f], t, level_values[f], options.aggregate);
        pairs.push_back({{location, original_values[f]}, {location, level_values[f]}});
        double shown_peak = 0;
        for (float v : level_values[f]) shown_peak = std::max<double>(shown_peak, std::abs(v));
        cell.peak_ratio.push_back(original_peak[f] > 0 ? shown_peak / original_peak[f] : 1.0);
        const double range = table.field_ranges[f];
        cell.peak_gap_pct.push_back(range > 0 ? 100 * (original_peak[f] - shown_peak) / range
                                              : 0.0);
      }
      auto r = hausdorff(original_step, level_steps[i], h, pairs);
      if (!keep_levels) {  // its memory back
        level_steps[i] = Surface();
        level_steps[i].topology = &level_surfaces[i];
      }
      if (!r) return Status::error(where + r.message());
      cell.hausdorff_pct = r->percent(r->hausdorff);
      cell.mean_pct = r->percent(r->mean);
      cell.rms_pct = r->percent(r->rms);
      cell.diagonal = r->diagonal;
      for (size_t f = 0; f < field_count; ++f) {
        const double range = table.field_ranges[f];
        auto pct = [&](double error) { return range > 0 ? 100 * error / range : 0.0; };
        cell.field_error_pct.push_back(pct(r->fields[f].max));
        cell.field_error_nearest_pct.push_back(pct(r->fields[f].nearest));
        cell.field_error_mean_pct.push_back(pct(r->fields[f].mean));
        row.max.field_error_mean_pct[f] =
            std::max(row.max.field_error_mean_pct[f], cell.field_error_mean_pct[f]);
        cell.field_error_node_pct.push_back(
            source_fields[source_index[f]].location == FieldLocation::kNode
                ? pct(node_error(model, representatives[i], original_values[f], level_values[f]))
                : kNaN);
        cell.field_error_at.push_back(r->fields[f].max_at);
        cell.field_error_untangled_pct.push_back(untangled ? cell.field_error_pct[f] : kNaN);
        double& untangled_max = row.max.field_error_untangled_pct[f];
        if (untangled && !(untangled_max >= cell.field_error_pct[f]))  // NaN: none yet
          untangled_max = cell.field_error_pct[f];
        if (cell.field_error_pct[f] > row.max.field_error_pct[f] || k == 0)
          row.max.field_error_pct[f] = cell.field_error_pct[f],
          row.max.field_error_at[f] = cell.field_error_at[f];
        row.max.field_error_nearest_pct[f] =
            std::max(row.max.field_error_nearest_pct[f], cell.field_error_nearest_pct[f]);
        // NaN (an element field) stays NaN: std::max keeps its first argument when unordered.
        row.max.field_error_node_pct[f] =
            std::max(cell.field_error_node_pct[f], row.max.field_error_node_pct[f]);
        row.max.peak_ratio[f] = std::min(row.max.peak_ratio[f], cell.peak_ratio[f]);
        row.max.peak_gap_pct[f] = std::max(row.max.peak_gap_pct[f], cell.peak_gap_pct[f]);
      }
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
