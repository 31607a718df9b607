// dynpm extract --refine: the selective navigator's mesh in the agreed order (docs/selective.md
// "Output"): existing vertices by ascending progressive id, active faces by ascending face id.
#include "extract_refined.h"

#include <cmath>
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "dynpm/io.h"
#include "dynpm/lod.h"
#include "family_inputs.h"
#include "json.h"
#include "outputs.h"
#include "report.h"

namespace dynpm::cli {

namespace {

// The values each field shows on the refined mesh at fractional step t (both neighbouring
// steps' aggregates, blended as the positions are).
std::vector<std::vector<float>> shown_fields(const SelectiveNavigator& nav,
                                             const SelectiveMesh& shown, double t,
                                             FieldAggregate aggregate) {
  const ProgressiveMesh& m = nav.mesh();
  const size_t last = m.step_count() - 1;
  const size_t t0 = std::min(static_cast<size_t>(std::floor(t)), last);
  const size_t t1 = std::min(t0 + 1, last);
  const float a = static_cast<float>(t - double(t0));
  std::vector<std::vector<float>> out;
  for (size_t f = 0; f < m.fields.size(); ++f) {
    std::vector<float> v0 = nav.field_values(f, t0, shown, aggregate);
    if (a != 0.0f && t1 != t0) {
      const std::vector<float> v1 = nav.field_values(f, t1, shown, aggregate);
      for (size_t i = 0; i < v0.size(); ++i) v0[i] += a * (v1[i] - v0[i]);
    }
    out.push_back(std::move(v0));
  }
  return out;
}

}  // namespace

int run_refined_extract(const Args& args, const std::string& verb, const std::string& output,
                        const std::optional<StepChoice>& step_choice, FieldAggregate aggregate) {
  auto usage = [&](const std::string& message) { return fail(verb, kExitUsage, message); };
  for (const char* level : {"--vertices", "--ratio", "--max-error", "--full"})
    if (args.has(level))
      return usage(std::string(level) +
                   " cannot go with --refine: give the level outside the regions with --elsewhere");
  const std::vector<std::string> requests = args.values("--refine");
  if (requests.empty()) return usage("--elsewhere needs at least one --refine REQUEST");
  const auto elsewhere_text = args.value("--elsewhere");
  if (!elsewhere_text)
    return usage(
        "--refine needs --elsewhere LEVEL (the level outside the regions: 5%, 20000 "
        "or error:0.01)");
  if (!step_choice) return usage("--refine needs --step T: the regions are taken at that step");
  std::vector<RefineTarget> targets;
  for (const std::string& r : requests) {
    auto target = parse_refine_target(r);
    if (!target) return usage("--refine " + target.message());
    targets.push_back(std::move(target).value());
  }
  auto elsewhere = parse_elsewhere(*elsewhere_text);
  if (!elsewhere) return usage("--elsewhere " + elsewhere.message());
  if (Status s = check_output_folder(output); !s.ok()) return fail(verb, kExitFailure, s.message());

  // Every split (the regions need the finest), the steps up to --step.
  DpmReadLimits limits;
  limits.last_step = step_choice->last_step_to_read();
  limits.fields = format_from_extension(output) != FileFormat::kObj;
  for (const RefineTarget& t : targets) limits.fields |= t.kind == RefineTarget::Kind::kField;
  std::optional<Phase> phase(std::in_place, "reading the model");
  const std::string& path = args.positional[0];
  auto mesh = read_dpm_of_variant(args, path, limits);
  if (!mesh) return fail(verb, kExitFailure, mesh.message());
  if (mesh->split_count() != mesh->full_split_count)
    return fail(verb, kExitFailure,
                path + " is a prefix of a file (" + std::to_string(mesh->split_count()) + " of " +
                    std::to_string(mesh->full_split_count) +
                    " splits): --refine needs the whole file");
  if (Status s = choose_variant(args, verb, path, *mesh); !s.ok())
    return fail(verb, kExitFailure, s.message());
  const size_t steps = mesh->step_count();
  auto step = step_choice->in_model(steps, path);
  if (!step) return usage(step.message());

  phase.emplace("refining");
  const SplitDependencies deps = derive_split_dependencies(*mesh);
  const RefineTargets refine(*mesh, deps);
  auto wanted = refine.request(*elsewhere, targets, *step);
  if (!wanted) return usage("--refine " + wanted.message());
  SelectiveNavigator nav(*mesh, deps);
  nav.set_active(*wanted);
  const SelectiveMesh shown = nav.active_mesh();

  // Positions of the existing vertices at the (fractional) step, in the output's order.
  std::vector<float> all(size_t{mesh->vertex_count()} * 3), xyz;
  Navigator full(*mesh);
  full.set_level(mesh->split_count());
  full.positions(*step, all);
  xyz.reserve(shown.vertices.size() * 3);
  for (uint32_t v : shown.vertices)
    xyz.insert(xyz.end(), &all[size_t{v} * 3], &all[size_t{v} * 3 + 3]);
  const auto values = shown_fields(nav, shown, *step, aggregate);
  std::vector<NamedValues> point, cell;
  for (size_t f = 0; f < mesh->fields.size(); ++f)
    (mesh->fields[f].info.location == FieldLocation::kElement ? cell : point)
        .push_back({mesh->fields[f].info.name, values[f]});

  WriteOptions write;
  write.binary = !args.has("--ascii");
  write.comment = "dynpm extract --refine: " + std::to_string(shown.vertices.size()) +
                  " vertices, step " + std::to_string(*step);
  StagedOutputs staged;
  if (Status s = write_mesh(staged.stage(output), shown.topology, xyz, write, point, cell); !s.ok())
    return fail(verb, kExitFailure, s.message());
  if (Status s = staged.commit(); !s.ok()) return fail(verb, kExitFailure, s.message());

  const uint32_t elsewhere_level = elsewhere_splits(*mesh, *elsewhere);
  if (args.has("--json")) {
    Json j;
    j.begin_object();
    j.value("vertices", uint64_t{nav.vertex_count()});
    j.value("faces", uint64_t{shown.topology.faces.size()});
    j.value("quads", uint64_t{shown.topology.quad_count()});
    j.value("triangles", uint64_t{shown.topology.triangle_count()});
    j.value("elsewhere_vertices", uint64_t{mesh->base_vertex_count + elsewhere_level});
    j.value("full_vertices", uint64_t{mesh->full_vertex_count});
    j.value("step", *step);
    j.begin_array("files");
    j.item(output);
    j.end_array();
    j.end_object();
    std::cout << j.str();
  } else {
    std::printf(
        "%u vertices, %zu faces (%zu quads, %zu triangles): %zu request(s) refined, "
        "elsewhere the level of %u vertices\nwrote %s\n",
        nav.vertex_count(), shown.topology.faces.size(), shown.topology.quad_count(),
        shown.topology.triangle_count(), targets.size(), mesh->base_vertex_count + elsewhere_level,
        output.c_str());
  }
  return kExitOk;
}

}  // namespace dynpm::cli
