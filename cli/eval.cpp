// dynpm eval: how far a progressive mesh is from the animation it was built from, at several
// resolutions and time steps (the paper's Table 2): two-sided Metro-style Hausdorff distance in
// % of the bounding-box diagonal over all steps (as 'dynpm hausdorff' for sequences). The
// measurement is evaluate_levels() (dynpm/pipeline.h); this file reads the flags and prints the
// table, the JSON and the plot (svg_plot.h).
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "args.h"
#include "commands.h"
#include "dynpm/pipeline.h"
#include "family_inputs.h"
#include "inputs.h"
#include "json.h"
#include "report.h"
#include "shared_flags.h"
#include "svg_plot.h"

namespace dynpm::cli {
namespace {

const VerbSpec kSpec{
    "eval",
    "dynpm eval ORIGINAL... --dpm MODEL.dpm --ratios 1,2,4,11 [--steps 0,12,24]\n"
    "                  [--field NAME,…] [--aggregate max|mean] [--facing-reach PCT]\n"
    "                  [--samples N] [--seed S] [--threads T] [--json OUT.json] [--plot OUT.svg]",
    "Measures a progressive mesh against the animation it was built from, as the paper's\n"
    "Table 2 does: for each resolution (--ratios, in % of the full vertex count) and each\n"
    "chosen time step (--steps, default the first, middle and last), the two-sided Hausdorff\n"
    "distance (Metro-style, as 'dynpm hausdorff') between the original at step t and the\n"
    "progressive mesh at step t, in % of the bounding-box diagonal over all steps.\n"
    "The column 'max' is the largest over every step of the animation (--max-over chosen: over\n"
    "the chosen steps only). With --field, also each field's error (the largest difference\n"
    "between the original's and the level's value at corresponding surface points, at the same\n"
    "samples, in % of the field's range over all steps) and its peak ratio (largest |value|\n"
    "shown / the original's largest at that step); at steps where the original passes through\n"
    "itself (sheets crossing, a run without contact), the field error's max over the other steps\n"
    "is reported beside. ORIGINAL is a mesh file or a quoted glob of step files.",
    {{"--dpm", "", true, "MODEL.dpm", "the progressive mesh (from dynpm build)"},
     kVariantFlag,
     {"--ratios", "", true, "R,R,…", "resolutions in % of the full vertex count, each in (0, 100]"},
     {"--steps", "", true, "T,T,…|every:N",
      "time steps of the table, or 'last' (default: first, middle, last); every:N samples steps\n"
      "0, N, 2N, … and the last, and makes the max column over those (a long run at scale)"},
     {"--max-over", "", true, "all|chosen", "steps of the 'max' column (default all)"},
     {"--field", "", true, "NAME,…", "result fields to measure (field error, peak ratio)"},
     {"--aggregate", "", true, "max|mean",
      "the value a coarse vertex or face shows (default max: the largest |value|)"},
     {"--facing-reach", "", true, "PCT",
      "field error: a sample matches the closest point facing its way if one is within PCT %\n"
      "of the diagonal farther than the closest point (default 1; 0: the closest point alone)"},
     kSamplesFlag,
     kSeedFlag,
     kThreadsFlag,
     {"--json", "", true, "OUT.json", "also write the results as JSON"},
     {"--plot", "", true, "OUT.svg", "also write an SVG plot of error against % of vertices"},
     kSplitPolygonsFlag,
     kIntegrationPointFlag,
     kProgressFlag,
     kQuietFlag}};

int fail_usage(const std::string& message) { return fail(kSpec.name, kExitUsage, message); }

int fail_input(const std::string& message) { return fail(kSpec.name, kExitFailure, message); }

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> items;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) items.push_back(item);
  if (!text.empty() && text.back() == ',') items.emplace_back();
  return items;
}

// The table (the paper's Table 2): rows = resolution, columns = steps and the max.
void print_table(const std::vector<std::string>& files, const FrameSource& frames,
                 const Topology& original, const std::string& dpm_path, const ProgressiveMesh& mesh,
                 const LevelsTable& table, const std::string& max_label,
                 const std::vector<std::string>& fields) {
  std::string inputs = files.front();
  if (files.size() > 1) inputs += " … " + files.back();
  std::printf("original      %s (%zu steps, %u vertices, %zu faces)\n", inputs.c_str(),
              frames.step_count(), original.vertex_count, original.faces.size());
  std::printf("model         %s (base %u vertices, %u splits)\n", dpm_path.c_str(),
              mesh.base_vertex_count, mesh.split_count());
  std::printf(
      "two-sided Hausdorff distance, %% of the bounding-box diagonal over all steps (%.4g)\n\n",
      table.reference_diagonal);
  std::printf("%10s %9s %9s", "% vertices", "vertices", "faces");
  for (size_t t : table.steps) std::printf(" %11s", ("step " + std::to_string(t)).c_str());
  std::printf("  %s\n", max_label.c_str());
  for (const LevelRow& row : table.rows) {
    std::printf("%10s %9u %9u", (format_number(row.ratio) + " %").c_str(), row.vertices, row.faces);
    for (const LevelDistance& c : row.steps) std::printf(" %11.4g", c.hausdorff_pct);
    std::printf("  %.4g (step %zu)\n", row.max.hausdorff_pct, row.max_step);
  }
  for (size_t f = 0; f < fields.size(); ++f) {
    std::printf("\nfield %s: field error, %% of its range over all steps (%.4g) / peak ratio\n",
                fields[f].c_str(), table.field_ranges[f]);
    std::printf("%10s", "% vertices");
    for (size_t t : table.steps) std::printf(" %17s", ("step " + std::to_string(t)).c_str());
    std::printf("  %s (peak ratio: smallest)\n", max_label.c_str());
    for (const LevelRow& row : table.rows) {
      std::printf("%10s", (format_number(row.ratio) + " %").c_str());
      for (const LevelDistance& c : row.steps)
        std::printf(" %9.4g / %5.3f", c.field_error_pct[f], c.peak_ratio[f]);
      std::printf("  %.4g / %.3f\n", row.max.field_error_pct[f], row.max.peak_ratio[f]);
    }
  }
  if (fields.empty() || table.crossings.empty()) return;
  std::string steps;
  for (const auto& [step, faces] : table.crossings)
    steps += (steps.empty() ? "" : ", ") + std::to_string(step) + " (" + std::to_string(faces) +
             " faces)";
  std::printf(
      "\nthe original passes through itself at step %s, where the field error measures\n"
      "the crossing too; the field error's max over the measured steps where it does not:\n",
      steps.c_str());
  for (const LevelRow& row : table.rows) {
    std::printf("%10s", (format_number(row.ratio) + " %").c_str());
    for (size_t f = 0; f < fields.size(); ++f)
      std::printf("  %s %.4g", fields[f].c_str(), row.max.field_error_untangled_pct[f]);
    std::printf("\n");
  }
}

// Each field's error and peak in one cell: {"NAME": {"field_error_pct", "peak_ratio",
// "peak_gap_pct"}}.
void fields_json(Json& j, const std::vector<std::string>& fields, const LevelDistance& cell) {
  if (fields.empty()) return;
  j.begin_object("fields");
  for (size_t f = 0; f < fields.size(); ++f) {
    j.begin_object(fields[f]);
    j.value("field_error_pct", cell.field_error_pct[f]);
    j.value("peak_ratio", cell.peak_ratio[f]);
    j.value("peak_gap_pct", cell.peak_gap_pct[f]);
    j.value("field_error_nearest_pct", cell.field_error_nearest_pct[f]);
    j.value("field_error_mean_pct", cell.field_error_mean_pct[f]);
    j.value("field_error_node_pct", cell.field_error_node_pct[f]);  // null: an element field
    j.begin_array("field_error_at");
    for (double c : cell.field_error_at[f]) j.item(c);
    j.end_array();
    // null: the original passes through itself at this step (in max: at every measured step)
    j.value("field_error_untangled_pct", cell.field_error_untangled_pct[f]);
    j.end_object();
  }
  j.end_object();
}

std::string table_json(const std::vector<std::string>& files, const FrameSource& frames,
                       const Topology& original, const std::string& dpm_path,
                       const ProgressiveMesh& mesh, const LevelsTable& table,
                       const LevelsOptions& options) {
  Json j;
  j.begin_object();
  j.begin_array("original");
  for (const std::string& f : files) j.item(f);
  j.end_array();
  j.value("model", dpm_path);
  j.value("vertices", uint64_t{original.vertex_count});
  j.value("faces", uint64_t{original.faces.size()});
  j.value("steps", uint64_t{frames.step_count()});
  j.value("seed", options.hausdorff.seed);
  j.value("model_diagonal", mesh.diagonal());
  j.begin_array("chosen_steps");
  for (size_t t : table.steps) j.item(int64_t(t));
  j.end_array();
  j.value("max_over", options.max_over_all_steps ? "all" : "chosen");
  if (!options.fields.empty()) {
    j.value("aggregate", options.aggregate == FieldAggregate::kMean ? "mean" : "max");
    j.value("facing_reach_pct", options.field_facing_reach_pct);
    j.begin_object("field_ranges");
    for (size_t f = 0; f < options.fields.size(); ++f)
      j.value(options.fields[f], table.field_ranges[f]);
    j.end_object();
    j.begin_array("self_crossings");  // steps where the original passes through itself
    for (const auto& [step, faces] : table.crossings) {
      j.begin_object();
      j.value("step", uint64_t{step});
      j.value("faces", uint64_t{faces});
      j.end_object();
    }
    j.end_array();
  }
  j.begin_array("ratios");
  for (const LevelRow& row : table.rows) {
    j.begin_object();
    j.value("ratio_pct", row.ratio);
    j.value("vertices", uint64_t{row.vertices});
    j.value("vertices_pct", 100.0 * row.vertices / mesh.full_vertex_count);
    j.value("faces", uint64_t{row.faces});
    j.value("level", uint64_t{row.level});
    j.value("level_error", row.error);
    j.value("level_error_pct", 100 * of_diagonal(row.error, mesh.diagonal()));
    j.begin_array("steps");
    for (size_t k = 0; k < table.steps.size(); ++k) {
      const LevelDistance& c = row.steps[k];
      j.begin_object();
      j.value("step", uint64_t{table.steps[k]});
      j.value("time", frames.step_time(table.steps[k]));
      j.value("diagonal", c.diagonal);
      j.value("hausdorff_pct", c.hausdorff_pct);
      j.value("mean_pct", c.mean_pct);
      j.value("rms_pct", c.rms_pct);
      fields_json(j, options.fields, c);
      j.end_object();
    }
    j.end_array();
    j.begin_object("max");
    j.value("hausdorff_pct", row.max.hausdorff_pct);
    j.value("step", uint64_t{row.max_step});
    j.value("mean_pct", row.max.mean_pct);
    j.value("rms_pct", row.max.rms_pct);
    fields_json(j, options.fields, row.max);
    j.end_object();
    j.end_object();
  }
  j.end_array();
  j.end_object();
  return j.str() + "\n";
}

}  // namespace

int run_eval(std::span<char* const> arguments) {
  Args args;
  if (auto exit_code = parse_verb_args(arguments, kSpec, args)) return *exit_code;
  const auto dpm_path = args.value("--dpm");
  const auto ratios_text = args.value("--ratios");
  if (args.positional.empty() || !dpm_path || !ratios_text)
    return fail(kSpec.name, kExitUsage,
                "needs the ORIGINAL animation, --dpm MODEL.dpm and --ratios", help_text(kSpec));

  LevelsOptions options;
  for (const std::string& item : split_list(*ratios_text)) {
    auto r = parse_number("--ratios", item, {0, 100, true});
    if (!r) return fail_usage(r.message() + " (percentages separated by commas)");
    options.ratios.push_back(*r);
  }
  std::vector<uint64_t> step_values;  // kLastStep: "last", resolved once the count is known
  constexpr uint64_t kLastStep = UINT64_MAX;
  uint64_t every = 0;  // --steps every:N, resolved once the step count is known
  if (auto text = args.value("--steps"); text && text->starts_with("every:")) {
    auto n = parse_whole("--steps every:N", text->substr(6), 1, 0xffffffffu);
    if (!n) return fail_usage(n.message());
    every = *n;
    options.max_over_all_steps = false;  // a sample: the max over what was measured
  } else if (text) {
    for (const std::string& item : split_list(*text)) {
      if (item == "last") {
        step_values.push_back(kLastStep);
        continue;
      }
      auto t = parse_whole("--steps", item, 0, 0xffffffffu);
      if (!t) return fail_usage(t.message() + " (step numbers or 'last' separated by commas)");
      step_values.push_back(*t);
    }
  }
  if (auto text = args.value("--max-over")) {
    if (*text != "all" && *text != "chosen") return fail_usage("--max-over is 'all' or 'chosen'");
    options.max_over_all_steps = *text == "all";
  }
  if (auto text = args.value("--field"))
    for (const std::string& name : split_list(*text)) {
      if (name.empty()) return fail_usage("--field needs field names separated by commas");
      options.fields.push_back(name);
    }
  if (auto text = args.value("--aggregate")) {
    if (*text != "max" && *text != "mean") return fail_usage("--aggregate is 'max' or 'mean'");
    options.aggregate = *text == "mean" ? FieldAggregate::kMean : FieldAggregate::kMaxAbs;
  }
  if (auto text = args.value("--facing-reach")) {
    auto reach = parse_number("--facing-reach", *text, kPercent);
    if (!reach) return fail_usage(reach.message() + " (% of the diagonal)");
    options.field_facing_reach_pct = *reach;
  }
  if (Status s = parse_sampling_flags(args, options.hausdorff); !s.ok())
    return fail_usage(s.message());
  const auto json_path = args.value("--json");
  const auto plot_path = args.value("--plot");

  // The original animation and the model.
  auto files = expand_inputs(args.positional);
  if (!files) return fail_input(files.message());
  auto stream = open_inputs(*files, args);
  if (!stream) return fail_input(stream.message());
  const Topology& original = stream->topology;
  const FrameSource& frames = *stream->frames;
  const size_t steps = frames.step_count();
  if (steps == 0) return fail_input(files->front() + ": no time steps");
  auto mesh = read_dpm(*dpm_path);
  if (!mesh) return fail_input(mesh.message());
  if (Status s = choose_variant(args, kSpec.name, *dpm_path, *mesh); !s.ok())
    return fail_input(s.message());
  if (Status s = check_built_from(original, frames, *mesh, *dpm_path); !s.ok())
    return fail_input(s.message());
  if (mesh->prefix)
    note(kSpec.name,
         *dpm_path + " is a prefix of a file; it holds " + std::to_string(mesh->split_count()) +
             " of " + std::to_string(mesh->full_split_count) + " splits, so the finest level is " +
             std::to_string(mesh->vertex_count()) + " vertices");
  if (every > 0) {
    for (uint64_t t = 0; t < steps; t += every) step_values.push_back(t);
    if (step_values.back() != steps - 1) step_values.push_back(steps - 1);
  }
  for (uint64_t t : step_values) {
    if (t == kLastStep) t = steps - 1;
    if (t > steps - 1)
      return fail_usage("--steps needs step numbers in [0, " + std::to_string(steps - 1) +
                        "] (the animation has " + std::to_string(steps) + " steps), got " +
                        std::to_string(t));
    options.steps.push_back(static_cast<size_t>(t));
  }

  options.model_name = *dpm_path;
  options.progress = [](size_t done, size_t total) { progress("measuring step", done, total); };
  auto table = evaluate_levels(original, frames, *mesh, options);
  if (!table) return fail_input(table.message());

  const std::string max_label = options.max_over_all_steps
                                    ? "max over all " + std::to_string(steps) + " steps"
                                    : "max over these steps";
  print_table(*files, frames, original, *dpm_path, *mesh, *table, max_label, options.fields);
  if (json_path) {
    const std::string json =
        table_json(*files, frames, original, *dpm_path, *mesh, *table, options);
    if (Status s = write_file_atomically(*json_path, json); !s.ok()) return fail_input(s.message());
    std::printf("\nwrote %s\n", json_path->c_str());
  }
  if (plot_path) {
    std::string model_name = *dpm_path;
    if (auto slash = model_name.find_last_of('/'); slash != std::string::npos)
      model_name = model_name.substr(slash + 1);
    const std::string svg = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n" +
                            svg_plot(*table, max_label, mesh->full_vertex_count,
                                     "dynpm eval: " + model_name + " against the original");
    if (Status s = write_file_atomically(*plot_path, svg); !s.ok()) return fail_input(s.message());
    std::printf("%swrote %s\n", json_path ? "" : "\n", plot_path->c_str());
  }
  return kExitOk;
}

}  // namespace dynpm::cli
