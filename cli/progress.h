// Progress of a verb's long phases on stderr, in one of three forms:
//   on a terminal   a live line, rewritten in place: "collapsing  45%  450000/1000000  81000/s
//                   7 s left", cleared when the phase ends;
//   otherwise       a plain line every 5 s of work and one at each phase's end, so that a
//                   redirected run (a batch job's log) shows where it is:
//                   "dynpm build: collapsing 45% (450000/1000000), 81000/s, 7 s left";
//   --progress json one object per line, for machines: {"phase":"collapsing","done":450000,
//                   "total":1000000,"elapsed_s":5.52,"eta_s":6.8} (elapsed and eta of the phase;
//                   eta_s null while unknown).
// --quiet (or --progress none) prints none of it. A phase without countable items (total ≤ 1:
// encoding, writing) shows its elapsed time only. A thread of its own prints the plain and json
// lines on time even while a phase calls no progress() (one long library call).
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "args.h"

namespace dynpm::cli {

inline const FlagSpec kProgressFlag{"--progress", "", true, "FORM",
                                    "progress on stderr: auto (a live line on a terminal, a "
                                    "line every 5 s otherwise), plain, json, none"};
inline const FlagSpec kQuietFlag{"--quiet", "-q", false, "",
                                 "no progress and no estimates on stderr (errors still)"};

// Reads --progress and --quiet for `verb` (which the plain lines name); the error is the usage
// message. Without them: auto.
Status configure_progress(const Args& args, const std::string& verb);

// The phase, the items done and the items in all (done == total ends the phase). A new phase
// name ends the one before.
void progress(std::string_view phase, size_t done, size_t total);

// A remark that is not an error, such as the build's memory estimate: "dynpm VERB: TEXT", or
// with --progress json the object `json` on a line of its own (every line stays JSON); nothing
// with --quiet.
void progress_remark(const std::string& text, const std::string& json);

// Before anything else is written to stderr: the live line is cleared (it is drawn again at the
// next progress()).
void clear_progress_line();

}  // namespace dynpm::cli
