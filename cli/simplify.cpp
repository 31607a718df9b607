// dynpm simplify: one mesh or animation, simplified, written as a mesh or a step sequence.
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>

#include "args.h"
#include "commands.h"
#include "dynpm/simplify.h"
#include "inputs.h"
#include "json.h"
#include "outputs.h"
#include "report.h"
#include "shared_flags.h"

namespace dynpm::cli {
namespace {

const VerbSpec kSpec{
    "simplify",
    "dynpm simplify INPUT... -o OUTPUT (--ratio R | --vertices N | --faces N | --max-error E)\n"
    "                      [--placement half|optimal] [--key-steps all|paper|auto:K|LIST] [--json]",
    "Simplifies a mixed triangle/quad mesh or animation by half-edge collapses (Wundrak et al.\n"
    "2006): a collapsed quad becomes a triangle, a collapsed triangle vanishes, legality by\n"
    "(P1*), (P2), (P3); cost by area-weighted quadrics, the max over the key steps. Boundaries,\n"
    "part boundaries and non-manifold edges (T-joints) only slide along themselves.\n"
    "OUTPUT is a mesh file (.obj .ply .vtk .vtu), or a pattern with {:03d} for an animation.\n"
    "--max-error is in units of the bounding-box diagonal (0.001), or in percent (0.1%).\n"
    "Key steps (paper §3): all; paper = first, last and the strongest deformation in between;\n"
    "auto:K = K steps, each the farthest (largest vertex displacement) from those chosen.\n"
    "Result fields count in the cost: by default every field, a change of its whole range\n"
    "multiplying the collapse's geometric error by 1 + 3 (--field-weight, --field-cost);\n"
    "--field NAME[:W] picks fields.",
    {{"--output", "-o", true, "OUTPUT", "output mesh, or pattern with {:03d} for several steps"},
     {"--ratio", "", true, "R", "keep this fraction of the vertices, e.g. 0.05"},
     {"--vertices", "", true, "N", "keep N vertices"},
     {"--faces", "", true, "N", "stop at N faces"},
     {"--max-error", "", true, "E", "stop before a collapse's error exceeds E"},
     {"--placement", "", true, "half|optimal", "half-edge (default, the paper) or optimal (QSlim)"},
     kKeyStepsFlag,
     kBoundaryWeightFlag,
     kFieldFlag,
     kFieldWeightFlag,
     kFieldCostFlag,
     kRegularizeFlag,
     kRoundsFlag,
     kIgnorePartsFlag,
     {"--ascii", "", false, "", "write PLY and VTK as text"},
     {"--json", "", false, "", "print the result as JSON"},
     kSplitPolygonsFlag,
     kIntegrationPointFlag,
     kProgressFlag,
     kQuietFlag}};

}  // namespace

int run_simplify(std::span<char* const> arguments) {
  Args args;
  if (auto exit_code = parse_verb_args(arguments, kSpec, args)) return *exit_code;
  if (auto exit_code = require_inputs_and_output(args, kSpec, "OUTPUT")) return *exit_code;
  const auto output = args.value("--output");
  auto usage = [](const std::string& message) { return fail(kSpec.name, kExitUsage, message); };
  auto level = parse_level_flags(args);
  if (!level) return usage(level.message());
  SimplifyOptions options;
  options.target_ratio = level->ratio;
  if (level->vertices) options.target_vertices = static_cast<uint32_t>(*level->vertices);
  if (level->faces) options.target_faces = static_cast<size_t>(*level->faces);
  if (level->max_error)
    options.max_error = level->max_error_in_percent ? *level->max_error / 100.0 : *level->max_error;
  if (!options.target_ratio && !options.target_vertices && !options.target_faces &&
      !options.max_error)
    return usage("give a target: --ratio, --vertices, --faces or --max-error");
  if (auto v = args.value("--placement")) {
    if (*v == "optimal")
      options.placement = Placement::kOptimal;
    else if (*v != "half")
      return usage("--placement is half or optimal");
  }
  KeyStepRule key_rule;
  if (Status s = parse_simplify_flags(args, options, key_rule); !s.ok()) return usage(s.message());
  if (!can_write(format_from_extension(*output)))
    return usage(*output + ": use .obj, .ply, .vtk or .vtu");

  auto stream = open_input_to_simplify(args, *output, options.checked);
  if (!stream) return fail(kSpec.name, kExitFailure, stream.message());
  std::optional<Phase> phase(std::in_place, "reading the input");
  const Topology& input = stream->topology;
  const FrameSource& frames = *stream->frames;
  if (Status s = check_cost_fields(options, frames); !s.ok()) return usage(s.message());
  const size_t steps = frames.step_count();
  const bool pattern = has_step_field(*output);
  if (steps > 1 && !pattern)
    return usage("the input has " + std::to_string(steps) +
                 " time steps; give an output pattern such as 'out_{:03d}.obj'");

  const auto start = std::chrono::steady_clock::now();
  // The simplifier's own phases (progress.h): its collapses are counted as they are made, also
  // where islands make them apart and tell them only at the end.
  options.progress = progress;
  auto key_steps = choose_key_steps(frames, key_rule, options.threads, options.progress);
  if (!key_steps) return fail(kSpec.name, kExitFailure, key_steps.message());
  options.key_steps = key_steps->steps;
  if (!args.has("--json"))
    for (const std::string& reason : key_steps->reasons)
      std::printf("key step  %s\n", reason.c_str());
  phase.emplace("simplifying");
  auto result = simplify(input, frames, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!result) return fail(kSpec.name, kExitFailure, result.message());

  // Write every step: the surviving vertices at their positions in that step.
  WriteOptions write;
  write.binary = !args.has("--ascii");
  std::vector<float> step(size_t{input.vertex_count} * 3), out;
  phase.emplace("writing the steps");
  StagedOutputs staged;
  for (size_t t = 0; t < steps; ++t) {
    progress("writing step", t + 1, steps);
    if (!result->key_step_positions.empty()) {
      out = result->key_step_positions[t];
    } else {
      if (Status s = frames.read_step(t, step); !s.ok())
        return fail(kSpec.name, kExitFailure, s.message());
      out.clear();
      for (uint32_t v : result->original_vertex)
        out.insert(out.end(), &step[size_t{v} * 3], &step[size_t{v} * 3] + 3);
    }
    auto path = pattern ? step_path(*output, t) : Result<std::string>(*output);
    write.comment = "dynpm simplify: step " + std::to_string(t) + ", time " +
                    std::to_string(frames.step_time(t));
    Status s = path ? write_mesh(staged.stage(*path), result->topology, out, write) : path.status();
    if (!s.ok()) return fail(kSpec.name, kExitFailure, s.message());
  }
  if (Status s = staged.commit(); !s.ok()) return fail(kSpec.name, kExitFailure, s.message());

  const Topology& t = result->topology;
  if (args.has("--json")) {
    Json j;
    j.begin_object();
    j.value("vertices_in", uint64_t{input.vertex_count});
    j.value("faces_in", uint64_t{input.faces.size()});
    j.value("quads_in", uint64_t{input.quad_count()});
    j.value("triangles_in", uint64_t{input.triangle_count()});
    j.value("vertices_out", uint64_t{t.vertex_count});
    j.value("faces_out", uint64_t{t.faces.size()});
    j.value("quads_out", uint64_t{t.quad_count()});
    j.value("triangles_out", uint64_t{t.triangle_count()});
    j.value("steps", uint64_t{steps});
    j.begin_array("key_steps");
    for (size_t k : result->key_steps) j.item(int64_t(k));
    j.end_array();
    j.value("collapses", uint64_t{result->collapses});
    j.value("max_error", result->max_error);
    j.value("target_reached", result->target_reached);
    j.value("stop_reason", result->stop_reason);
    j.value("seconds", seconds);
    j.value("peak_rss_mb", peak_rss_mb());
    j.end_object();
    std::cout << j.str();
  } else {
    std::printf("input   %u vertices, %zu faces (%zu quads, %zu triangles), %zu steps\n",
                input.vertex_count, input.faces.size(), input.quad_count(), input.triangle_count(),
                steps);
    std::printf("output  %u vertices, %zu faces (%zu quads, %zu triangles)\n", t.vertex_count,
                t.faces.size(), t.quad_count(), t.triangle_count());
    std::printf("key steps %zu of %zu; %zu collapses; largest error %.4g%% of the diagonal\n",
                result->key_steps.size(), steps, result->collapses, 100 * result->max_error);
    std::printf("%s%s; %.3f s; peak memory %.0f MB\n",
                result->target_reached ? "" : "stopped early: ", result->stop_reason.c_str(),
                seconds, peak_rss_mb());
  }
  return kExitOk;
}

}  // namespace dynpm::cli
