// Child processes of 'dynpm batch': a build run as "dynpm build …" with its output in a log
// file, and a command whose standard output is read back (sbatch --parsable).
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

#include "dynpm/result.h"

namespace dynpm::cli {

// The running dynpm binary's own path (/proc/self/exe), so that children and Slurm scripts run
// the very same program.
Result<std::string> own_executable();

// Starts `argv` (argv[0] is the program, looked up on PATH when it has no '/') with stdin from
// /dev/null and stdout and stderr appended to `log`. Returns the child's id.
Result<pid_t> start_process(const std::vector<std::string>& argv, const std::string& log);

// Waits for any child; its id and what became of it ("" when it exited with 0, otherwise
// "exit code N" or "killed by signal N"). An error when there is no child.
struct Ended {
  pid_t pid = 0;
  std::string failure;
};
Result<Ended> wait_for_any_child();

// Runs `argv` to its end with stdout captured (stderr passes through); an error names the
// command and how it ended.
Result<std::string> run_and_capture(const std::vector<std::string>& argv);

// A word for a POSIX shell: 'it''s' quoted so that nothing in it is expanded.
std::string shell_quoted(const std::string& word);

}  // namespace dynpm::cli
