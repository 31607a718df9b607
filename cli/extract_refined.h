// dynpm extract --refine: selective refinement (docs/selective.md), the regions at full
// resolution and the rest at the --elsewhere level, at one step.
#pragma once

#include <optional>
#include <string>

#include "args.h"
#include "dynpm/progressive.h"
#include "shared_flags.h"

namespace dynpm::cli {

// The --refine and --elsewhere flags of extract (in its VerbSpec; inline, so that they are
// made before the VerbSpec that copies them).
inline const FlagSpec kRefineFlag{
    "--refine", "", true, "REQUEST",
    "full resolution where REQUEST says (repeatable; a union): box:X0,Y0,Z0,X1,Y1,Z1,\n"
    "sphere:X,Y,Z,R, part:3,7, field:NAME>V or field:NAME<V, moved:>D (from step 0),\n"
    "view:EYE=x,y,z;AT=x,y,z;FOV=deg;H=px;PX=p[;UP=x,y,z][;W=px][;BUDGET=n] (what a camera\n"
    "sees with an error above PX pixels; UP defaults to 0,0,1, W to H; BUDGET caps the\n"
    "vertices, passed by at most one split's dependencies; quote it: ';' is the shell's)"};
inline const FlagSpec kElsewhereFlag{
    "--elsewhere", "", true, "LEVEL",
    "the level outside the --refine regions: 5% (of the vertices), a "
    "vertex count, or error:E (absolute)"};

// Runs extract with --refine/--elsewhere given; `step_choice` as parsed (required here). Checks
// every request before the model is read; writes nothing on an error.
int run_refined_extract(const Args& args, const std::string& verb, const std::string& output,
                        const std::optional<StepChoice>& step_choice, FieldAggregate aggregate);

}  // namespace dynpm::cli
