// A reader run in a forked child process, so that a crash or a hang in a library we do not
// control (HDF5 under netCDF-4) cannot take dynpm down: the child dies, dynpm reports a damaged
// file. Issue 16: single-word corruptions of an HDF5 Exodus file made libhdf5 SIGSEGV in nc_open.
//
//   parent                                  child (fork at open time, dynpm single-threaded)
//   open_in_child(path, …, open) ──fork──▶  stream = open(options)
//                                 ◀──────── 'O' topology, steps, times, fields, warnings  or
//                                           'E' the reader's own error message
//   frames->read_step(t)          ───────▶  'S' t
//                                 ◀──────── 'D' floats  or  'E' message
//   frames->read_field(f, t)      ───────▶  'F' f t     (same answers)
//   ~FrameSource                  ── EOF ─▶ _exit(0)   (and SIGKILL, then waitpid)
//
// The child stays alive serving one step at a time, so memory stays what the reader's own
// streaming needs (a 5 M-node × 100-step file is never decoded whole). Any death of the child
// (a signal, a non-zero exit: sanitizers exit 1) or no answer for 10 s plus the time to read the
// whole file at 8 MiB/s becomes
// "<path>: damaged <library> file (the <library> library crashed reading it: …)" on whichever
// call was waiting; later calls repeat it.
#pragma once

#include <functional>
#include <string>

#include "dynpm/core.h"
#include "dynpm/io.h"

namespace dynpm::io {

// Calls `open` in a child process; `library` names what may crash ("HDF5"). The returned
// stream's frames are read through the child. options.warn receives the child's warnings.
// It forks: call it while no other thread holds a lock the reader needs (dynpm opens its
// inputs before any worker thread starts; the simplifier's threads end with each pass).
Result<AnimationStream> open_in_child(
    const std::string& path, const ReadOptions& options, const char* library,
    const std::function<Result<AnimationStream>(const ReadOptions&)>& open);

}  // namespace dynpm::io
