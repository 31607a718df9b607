// dynpm convert: a mesh or animation from one format to another, one step at a time.
#include <iostream>
#include <vector>

#include "args.h"
#include "commands.h"
#include "inputs.h"
#include "outputs.h"
#include "report.h"

namespace dynpm::cli {
namespace {

const VerbSpec kSpec{
    "convert",
    "dynpm convert INPUT... -o OUTPUT [--ascii] [--split-polygons]",
    "Converts a mesh or an animation (one file per time step: a list or a glob, sorted\n"
    "naturally) between OBJ, PLY and VTK legacy polydata. The output format follows the\n"
    "extension of OUTPUT. An animation of several steps needs a step field in OUTPUT, e.g.\n"
    "'out/frame_{:03d}.ply'. Quads stay quads; part ids, element ids and node ids travel\n"
    "where the format can hold them (PLY, VTK). Steps are streamed: one in memory at a time.\n"
    "Each file is written under a temporary name and renamed when complete.",
    {{"--output", "-o", true, "OUTPUT", "output file, or pattern with {:03d} for several steps"},
     {"--ascii", "", false, "", "write PLY and VTK as text instead of binary"},
     kSplitPolygonsFlag,
     kIntegrationPointFlag,
     kProgressFlag,
     kQuietFlag}};

}  // namespace

int run_convert(std::span<char* const> arguments) {
  Args args;
  if (auto exit_code = parse_verb_args(arguments, kSpec, args)) return *exit_code;
  if (auto exit_code = require_inputs_and_output(args, kSpec, "OUTPUT")) return *exit_code;
  const auto output = args.value("--output");
  if (!can_write(format_from_extension(*output)))
    return fail(kSpec.name, kExitUsage,
                *output +
                    ": cannot tell the output format from the extension (use .obj, .ply, "
                    ".vtk or .vtu)");
  Phase phase("reading and writing the steps");
  auto stream = open_inputs(args.positional, args);
  if (!stream) return fail(kSpec.name, kExitFailure, stream.message());
  const FrameSource& frames = *stream->frames;
  const size_t steps = frames.step_count();
  const bool pattern = has_step_field(*output);
  if (steps > 1 && !pattern)
    return fail(kSpec.name, kExitUsage,
                "the input has " + std::to_string(steps) +
                    " time steps; give an output pattern with a step field, e.g. 'frame_{:03d}" +
                    output->substr(output->rfind('.')) + "'");

  WriteOptions options;
  options.binary = !args.has("--ascii");
  std::vector<float> xyz(size_t{frames.vertex_count()} * 3);
  // Result fields travel along: per node as point data, per element as cell data.
  const std::vector<FieldInfo> fields = frames.fields();
  std::vector<std::vector<float>> values(fields.size());
  for (size_t f = 0; f < fields.size(); ++f)
    values[f].resize(fields[f].location == FieldLocation::kElement ? stream->topology.face_count()
                                                                   : size_t{frames.vertex_count()});
  std::string first, last;
  StagedOutputs staged;
  for (size_t t = 0; t < steps; ++t) {
    progress("converting step", t + 1, steps);
    auto path = pattern ? step_path(*output, t) : Result<std::string>(*output);
    if (!path) return fail(kSpec.name, kExitUsage, path.message());
    if (Status s = frames.read_step(t, xyz); !s.ok())
      return fail(kSpec.name, kExitFailure, s.message());
    std::vector<NamedValues> point_fields, cell_fields;
    for (size_t f = 0; f < fields.size(); ++f) {
      if (Status s = frames.read_field(f, t, values[f]); !s.ok())
        return fail(kSpec.name, kExitFailure, s.message());
      (fields[f].location == FieldLocation::kElement ? cell_fields : point_fields)
          .push_back({fields[f].name, values[f]});
    }
    options.comment =
        "dynpm: step " + std::to_string(t) + ", time " + std::to_string(frames.step_time(t));
    if (Status s = write_mesh(staged.stage(*path), stream->topology, xyz, options, point_fields,
                              cell_fields);
        !s.ok())
      return fail(kSpec.name, kExitFailure, s.message());
    (t == 0 ? first : last) = *path;
  }
  if (Status s = staged.commit(); !s.ok()) return fail(kSpec.name, kExitFailure, s.message());
  std::cout << "wrote " << steps << (steps == 1 ? " step: " : " steps: ") << first
            << (steps > 1 ? " … " + last : "") << " (" << stream->topology.vertex_count
            << " vertices, " << stream->topology.quad_count() << " quads, "
            << stream->topology.triangle_count() << " triangles)\n";
  return kExitOk;
}

}  // namespace dynpm::cli
