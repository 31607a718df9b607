// What a verb tells the user besides its result: the one way a verb fails ("dynpm VERB:
// message" on stderr and an exit code), notes, progress on a terminal, and the out-of-memory
// message with the phase it happened in.
#pragma once

#include <cstddef>
#include <string>

#include "progress.h"  // progress(), which every verb with long phases calls

namespace dynpm::cli {

// What stops a verb, said one way: "dynpm VERB: message" on stderr, then a blank line and
// `help` if one is given (a usage error that lacks an argument). Returns `exit_code`
// (commands.h) for the verb to return.
int fail(const std::string& verb, int exit_code, const std::string& message,
         const std::string& help = "");

// A remark that does not stop the verb: "dynpm VERB: note: message" on stderr.
void note(const std::string& verb, const std::string& message);

// What a verb is doing, for the out-of-memory message ("out of memory while simplifying"). Phases
// nest; when an exception leaves one, the innermost is remembered (the handler in main() runs
// after the phases are gone).
class Phase {
 public:
  explicit Phase(const char* what);
  Phase(const Phase&) = delete;
  Phase& operator=(const Phase&) = delete;
  ~Phase();
  // The phase an exception left last, or nullptr.
  static const char* failed();

 private:
  const char* what_;
  int exceptions_;
};

// The message and exit code for running out of memory (std::bad_alloc, std::length_error):
// "dynpm build: out of memory while simplifying (peak 812 MB resident; …)".
int out_of_memory(const std::string& verb);

// A length as a fraction of the bounding-box diagonal; 0 when the diagonal is 0 (every vertex at
// one point), so that no report prints "-nan%".
double of_diagonal(double length, double diagonal);

// The process's peak resident memory in MB (VmHWM), or 0 where /proc is not there.
double peak_rss_mb();

}  // namespace dynpm::cli
