// What every verb that reads a mesh or an animation does first: globs → files → one
// AnimationStream, with reader notes on stderr and the checks the verb needs.
#pragma once

#include <span>
#include <string>

#include "args.h"
#include "dynpm/io.h"

namespace dynpm::cli {

// The flag of every verb that reads meshes (ReadOptions::split_polygons).
inline const FlagSpec kSplitPolygonsFlag{"--split-polygons", "", false, "",
                                         "fan-split faces with more than 4 corners"};

// What a verb needs of its input before it starts working.
enum class InputChecks {
  kNone,         // 'dynpm info': validate() lists every problem, nothing is refused
  kFinite,       // reading a step with a NaN or infinite coordinate fails (file, step, vertex)
  kSimplifiable  // kFinite, and faces that validate() calls errors fail at once (file, face)
};

// Globs → files, then open them as one animation; reader notes go to stderr.
Result<AnimationStream> open_inputs(std::span<const std::string> arguments, bool split_polygons,
                                    InputChecks checks = InputChecks::kFinite);

}  // namespace dynpm::cli
