// The verbs of the dynpm command. Each takes the arguments after the verb and returns the
// process exit code: 0 success, 1 bad input or failed work, 2 bad usage.
#pragma once

#include <span>
#include <string>
#include <utility>
#include <vector>

#include "dynpm/io.h"

namespace dynpm::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitFailure = 1;
inline constexpr int kExitUsage = 2;
inline constexpr int kExitInvalidMesh = 3;  // read fine, but validate() found errors

int run_info(std::span<char* const> arguments);
int run_convert(std::span<char* const> arguments);
int run_hausdorff(std::span<char* const> arguments);
int run_simplify(std::span<char* const> arguments);
int run_build(std::span<char* const> arguments);
int run_extract(std::span<char* const> arguments);
int run_eval(std::span<char* const> arguments);
int run_view(std::span<char* const> arguments);

// Before a long run: an error if `output` (a file or a step pattern) is a folder or its folder
// does not exist, so that the work is not lost at the end.
Status check_output_folder(const std::string& output);

// What a verb needs of its input before it starts working.
enum class InputChecks {
  kNone,         // 'dynpm info': validate() lists every problem, nothing is refused
  kFinite,       // reading a step with a NaN or infinite coordinate fails (file, step, vertex)
  kSimplifiable  // kFinite, and faces that validate() calls errors fail at once (file, face)
};

// Globs → files, then open them as one animation; reader notes go to stderr.
Result<AnimationStream> open_inputs(std::span<const std::string> arguments, bool split_polygons,
                                    InputChecks checks = InputChecks::kFinite);

// The files of one output (a mesh, or one per step) are written under temporary names beside
// their targets and renamed into place only when every one is written, so a run that fails
// half-way leaves no output and keeps the files it would have replaced. A killed run can leave
// its staged files: "<stem>.tmp-<pid><ext>" (the extension picks the format); the next run that
// commits the same target removes them (remove_stale_temporaries, one listing per folder).
class StagedOutputs {
 public:
  StagedOutputs() = default;
  StagedOutputs(const StagedOutputs&) = delete;
  StagedOutputs& operator=(const StagedOutputs&) = delete;
  ~StagedOutputs();  // removes what was staged and not committed

  // Where to write `path` for now.
  std::string stage(const std::string& path);
  // Renames every staged file to its target, in order.
  Status commit();

 private:
  std::vector<std::pair<std::string, std::string>> files_;  // (staged, target)
};

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

// Progress on stderr ("label 12/26"), only when stderr is a terminal.
void progress(const std::string& label, size_t done, size_t total);

// The process's peak resident memory in MB (VmHWM), or 0 where /proc is not there.
double peak_rss_mb();

}  // namespace dynpm::cli
