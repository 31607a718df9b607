// dynpm extract: a progressive mesh at a chosen resolution and time step, as a mesh file.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>

#include "args.h"
#include "commands.h"
#include "dynpm/io.h"
#include "dynpm/lod.h"
#include "extract_refined.h"
#include "family_inputs.h"
#include "json.h"
#include "outputs.h"
#include "report.h"
#include "shared_flags.h"

namespace dynpm::cli {
namespace {

const VerbSpec kSpec{
    "extract",
    "dynpm extract MODEL.dpm (--vertices N | --ratio R | --max-error E | --full) [--step T]\n"
    "                     -o OUTPUT [--ascii] [--json]\n"
    "       dynpm extract MODEL.dpm --step T --refine REQUEST... --elsewhere LEVEL -o OUTPUT",
    "Writes the progressive mesh at one resolution: N vertices, a fraction R of the full\n"
    "vertex count, or the coarsest level whose simplification error is at most E (absolute,\n"
    "or '0.5%' of the bounding-box diagonal). --step T picks a time step ('last': the last\n"
    "one); a fractional T interpolates between steps. Without --step every step is written:\n"
    "OUTPUT must then hold a {:03d} field. Fully refined (--full), vertices and faces come in\n"
    "the input's order, so the output compares equal to the input (exactly, for a --lossless\n"
    "build); at other levels they come in progressive order (base first). Coordinates\n"
    "round-trip float32.\n"
    "Result fields are written as point data (node fields) and cell data (element fields) in\n"
    "VTK and VTU, and as vertex and face properties in PLY: at a coarse level each vertex or\n"
    "face shows the aggregate of the original ones it stands for (--aggregate).\n"
    "Only what the output needs is decoded: the splits up to its level and the steps up to\n"
    "--step (with result fields, every split: a coarse face shows the peak of finer ones).\n"
    "With --refine (docs/selective.md) the requested regions are at full resolution at step T\n"
    "(a view: wherever a camera would see an error above PX pixels, within a BUDGET of\n"
    "vertices) and the rest at the --elsewhere level; vertices come in progressive order,\n"
    "faces too.",
    {{"--output", "-o", true, "OUTPUT", "mesh file (.obj .ply .vtk .vtu) or pattern with {:03d}"},
     {"--vertices", "", true, "N", "resolution as a vertex count"},
     {"--ratio", "", true, "R", "resolution as a fraction of the full vertex count"},
     {"--max-error", "", true, "E", "coarsest level with error ≤ E (absolute, or E%)"},
     {"--full", "", false, "", "the fully refined mesh (the input)"},
     {"--step", "", true, "T", "time step (fractional interpolates; 'last'); default every step"},
     kVariantFlag,
     {"--aggregate", "", true, "max|mean",
      "what a coarse vertex or face shows of the ones it stands for: the value of largest\n"
      "magnitude (max, default: a peak is never hidden) or their mean"},
     kRefineFlag,
     kElsewhereFlag,
     {"--ascii", "", false, "", "write PLY and VTK as text"},
     {"--json", "", false, "", "print what was written as JSON"}}};

int fail_usage(const std::string& message) { return fail(kSpec.name, kExitUsage, message); }

// The values every field shows at this level and (fractional) step t, in the output's order:
// the aggregates of the two neighbouring steps, blended linearly as the positions are.
struct ShownFields {
  std::vector<NamedValues> point, cell;
  std::vector<std::vector<float>> values;  // per field

  void compute(const Navigator& nav, double t, FieldAggregate aggregate,
               const OriginalOrder* order) {
    const ProgressiveMesh& m = nav.mesh();
    const size_t last = m.step_count() - 1;
    const size_t t0 = std::min(static_cast<size_t>(std::floor(t)), last);
    const size_t t1 = std::min(t0 + 1, last);
    const float a = static_cast<float>(t - static_cast<double>(t0));
    point.clear();
    cell.clear();
    values.resize(m.fields.size());
    std::vector<float> v0, v1;
    for (size_t f = 0; f < m.fields.size(); ++f) {
      const bool per_face = m.fields[f].info.location == FieldLocation::kElement;
      const size_t n = per_face ? nav.face_count() : nav.vertex_count();
      v0.resize(n);
      nav.field_values(f, t0, v0, aggregate);
      if (a != 0.0f && t1 != t0) {
        v1.resize(n);
        nav.field_values(f, t1, v1, aggregate);
        for (size_t i = 0; i < n; ++i) v0[i] += a * (v1[i] - v0[i]);
      }
      std::vector<float>& out = values[f];
      out.resize(n);
      const std::vector<uint32_t>* to_progressive =
          order ? &(per_face ? order->face_of_original : order->vertex_of_original) : nullptr;
      for (size_t i = 0; i < n; ++i) out[i] = v0[to_progressive ? (*to_progressive)[i] : i];
      (per_face ? cell : point).push_back({m.fields[f].info.name, out});
    }
  }
};

}  // namespace

int run_extract(std::span<char* const> arguments) {
  Args args;
  if (auto exit_code = parse_verb_args(arguments, kSpec, args)) return *exit_code;
  const auto output = args.value("--output");
  if (args.positional.size() != 1 || !output)
    return fail(kSpec.name, kExitUsage, "needs one MODEL.dpm and -o OUTPUT", help_text(kSpec));
  if (!can_write(format_from_extension(*output)))
    return fail_usage(*output + ": use .obj, .ply, .vtk or .vtu");
  FieldAggregate aggregate = FieldAggregate::kMaxAbs;
  if (auto v = args.value("--aggregate")) {
    if (*v == "mean")
      aggregate = FieldAggregate::kMean;
    else if (*v != "max")
      return fail_usage("--aggregate is max or mean, got " + quoted_value(*v));
  }
  // The model's last step is known once it is read (below).
  auto step_choice = parse_step_flag(args);
  if (!step_choice) return fail_usage(step_choice.message());
  if (args.has("--refine") || args.has("--elsewhere"))
    return run_refined_extract(args, kSpec.name, *output, *step_choice, aggregate);
  std::optional<double> step;
  const int choices =
      args.has("--vertices") + args.has("--ratio") + args.has("--max-error") + args.has("--full");
  if (choices != 1) return fail_usage("give one of --vertices, --ratio, --max-error, --full");
  if (!*step_choice && !has_step_field(*output))
    return fail_usage(
        "without --step every step is written; give a pattern such as "
        "'out_{:03d}.obj'");

  // The resolution, checked before the model is read.
  auto level = parse_level_flags(args);
  if (!level) return fail_usage(level.message());

  if (Status s = check_output_folder(*output); !s.ok())
    return fail(kSpec.name, kExitFailure, s.message());

  // Only what the output needs is decoded: the splits up to its level, the steps up to its step.
  DpmReadLimits limits;
  limits.vertices = level->vertices ? std::optional<uint32_t>(static_cast<uint32_t>(
                                          std::min<double>(*level->vertices, UINT32_MAX)))
                                    : std::nullopt;
  limits.ratio = level->ratio;
  limits.error = level->max_error;
  if (level->max_error && level->max_error_in_percent) {
    limits.error = *level->max_error / 100.0;
    limits.error_of_diagonal = true;
  }
  if (*step_choice) limits.last_step = (*step_choice)->last_step_to_read();
  limits.fields = format_from_extension(*output) != FileFormat::kObj;  // OBJ holds no fields
  std::optional<Phase> phase(std::in_place, "reading the model");
  auto mesh = read_dpm_of_variant(args, args.positional[0], limits);
  if (!mesh) return fail(kSpec.name, kExitFailure, mesh.message());
  if (mesh->prefix)  // also when --step limited the read: the level asked may not be there
    note(kSpec.name, args.positional[0] + " is a prefix of a file; it holds " +
                         std::to_string(mesh->split_count()) + " of " +
                         std::to_string(mesh->full_split_count) + " splits");
  if (Status s = choose_variant(args, kSpec.name, args.positional[0], *mesh); !s.ok())
    return fail(kSpec.name, kExitFailure, s.message());
  const size_t steps = mesh->step_count();
  if (*step_choice) {
    auto t = (*step_choice)->in_model(steps, args.positional[0]);
    if (!t) return fail_usage(t.message());
    step = *t;
  }

  phase.emplace("extracting the meshes");
  Navigator nav(*mesh);
  if (level->vertices)  // past the full count: the full mesh
    nav.set_vertex_count(static_cast<uint32_t>(*level->vertices));
  else if (level->ratio)
    nav.set_vertex_count(
        static_cast<uint32_t>(std::lround(*level->ratio * mesh->full_vertex_count)));
  else if (level->max_error)
    nav.set_error(level->max_error_in_percent ? *level->max_error / 100.0 * mesh->diagonal()
                                              : *level->max_error);
  else
    nav.set_level(mesh->split_count());

  // Fully refined: the input's order. Otherwise the navigator's (progressive) order. (Reading
  // only the steps up to --step leaves the mesh incomplete, yet every split is there.)
  const bool full = nav.level() == mesh->full_split_count;
  Topology topology;
  std::vector<uint32_t> vertex_order;  // output vertex → navigator vertex
  std::optional<OriginalOrder> ordered;
  if (full) {
    auto in_input_order = original_order(nav);
    if (!in_input_order) return fail(kSpec.name, kExitFailure, in_input_order.message());
    ordered = std::move(*in_input_order);
    topology = std::move(ordered->topology);
    vertex_order = ordered->vertex_of_original;
  } else {
    topology = nav.topology();
  }

  WriteOptions write;
  write.binary = !args.has("--ascii");
  std::vector<float> positions(size_t{nav.vertex_count()} * 3), out(positions.size());
  std::vector<std::string> written;
  StagedOutputs staged;
  ShownFields shown;
  const size_t count = step ? 1 : steps;
  for (size_t k = 0; k < count; ++k) {
    const double t = step ? *step : double(k);
    nav.positions(t, positions);
    const std::span<const float> xyz =
        vertex_order.empty() ? std::span<const float>(positions) : std::span<const float>(out);
    if (!vertex_order.empty())
      for (size_t v = 0; v < vertex_order.size(); ++v)
        std::copy_n(&positions[size_t{vertex_order[v]} * 3], 3, &out[v * 3]);
    auto path = step ? Result<std::string>(*output) : step_path(*output, k);
    if (!path) return fail_usage(path.message());
    write.comment = "dynpm extract: " + std::to_string(nav.vertex_count()) + " vertices, step " +
                    std::to_string(t) + ", time " +
                    std::to_string(mesh->times[std::min(size_t(t), steps - 1)]);
    shown.compute(nav, t, aggregate, ordered ? &*ordered : nullptr);
    if (Status s = write_mesh(staged.stage(*path), topology, xyz, write, shown.point, shown.cell);
        !s.ok())
      return fail(kSpec.name, kExitFailure, s.message());
    written.push_back(*path);
  }
  if (Status s = staged.commit(); !s.ok()) return fail(kSpec.name, kExitFailure, s.message());

  if (args.has("--json")) {
    Json j;
    j.begin_object();
    j.value("vertices", uint64_t{nav.vertex_count()});
    j.value("faces", uint64_t{topology.faces.size()});
    j.value("quads", uint64_t{topology.quad_count()});
    j.value("triangles", uint64_t{topology.triangle_count()});
    j.value("level", uint64_t{nav.level()});
    j.value("error", nav.error());
    j.value("error_pct", 100 * of_diagonal(nav.error(), mesh->diagonal()));
    j.value("full", full);
    j.begin_array("fields");
    for (size_t f = 0; f < mesh->fields.size(); ++f) {
      const ProgressiveField& field = mesh->fields[f];
      j.begin_object();
      j.value("name", field.info.name);
      j.value("location", to_string(field.info.location));
      j.value("unit", field.info.unit);
      j.value("field_error_pct", 100 * nav.field_error(f));
      j.end_object();
    }
    j.end_array();
    j.begin_array("files");
    for (const std::string& f : written) j.item(f);
    j.end_array();
    j.end_object();
    std::cout << j.str();
  } else {
    std::printf(
        "%u vertices, %zu faces (%zu quads, %zu triangles); error %.4g (%.3g%% of the "
        "diagonal)\nwrote %s%s\n",
        nav.vertex_count(), topology.faces.size(), topology.quad_count(), topology.triangle_count(),
        nav.error(), 100 * of_diagonal(nav.error(), mesh->diagonal()), written.front().c_str(),
        written.size() > 1 ? " …" : "");
  }
  return kExitOk;
}

}  // namespace dynpm::cli
