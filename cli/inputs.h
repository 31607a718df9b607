// What every verb that reads a mesh or an animation does first: globs → files → one
// AnimationStream, with reader notes on stderr and the checks the verb needs.
#pragma once

#include <optional>
#include <span>
#include <string>

#include "args.h"
#include "dynpm/io.h"

namespace dynpm::cli {

// The flag of every verb that reads meshes (ReadOptions::split_polygons).
inline const FlagSpec kSplitPolygonsFlag{"--split-polygons", "", false, "",
                                         "fan-split faces with more than 4 corners"};
// ReadOptions::integration_point.
inline const FlagSpec kIntegrationPointFlag{
    "--integration-point", "", true, "POINT",
    "shell element results (d3plot) at mid (default), top, bottom or max over the points"};

// What a verb needs of its input before it starts working.
enum class InputChecks {
  kNone,         // 'dynpm info': validate() lists every problem, nothing is refused
  kFinite,       // reading a step with a NaN or infinite coordinate fails (file, step, vertex)
  kSimplifiable  // kFinite, and faces that validate() calls errors fail at once (file, face)
};

// Globs → files, then open them as one animation with the reading flags of args
// (--split-polygons, --integration-point); reader notes go to stderr. With kSimplifiable,
// `checked` (when given) gets the proof that the faces were checked (SimplifyOptions::checked).
Result<AnimationStream> open_inputs(std::span<const std::string> arguments, const Args& args,
                                    InputChecks checks = InputChecks::kFinite,
                                    std::optional<ValidationProof>* checked = nullptr);

// A verb that reads INPUT... and writes -o OUTPUT: the exit code of the usage failure when
// either is missing ("dynpm convert: needs INPUT... and -o OUTPUT", then the help).
std::optional<int> require_inputs_and_output(const Args& args, const VerbSpec& spec,
                                             const std::string& output_name);

// The input of 'build' and 'simplify': first the output's folder (so that the work is not lost
// at the end), then the inputs opened with InputChecks::kSimplifiable ("reading the input");
// `checked` gets the proof of that check, for the simplifier not to check again.
Result<AnimationStream> open_input_to_simplify(const Args& args, const std::string& output,
                                               std::optional<ValidationProof>& checked);

// open_input_to_simplify() in two parts, for a verb that reads the steps while the faces are
// checked (the check is one core's work for about as long as reading every step): the output's
// folder and the inputs opened with InputChecks::kFinite, then check_input_faces(), the faces'
// check of kSimplifiable (its message names `first_file`), which may run on another thread.
struct InputToSimplify {
  AnimationStream stream;
  std::string first_file;
};
Result<InputToSimplify> open_input_unchecked(const Args& args, const std::string& output);
Status check_input_faces(const InputToSimplify& input, std::optional<ValidationProof>& checked);

}  // namespace dynpm::cli
