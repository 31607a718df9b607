// 'dynpm batch --slurm': the builds as one Slurm job array (a task per variant, each running
// 'dynpm batch --task I', idempotent: an up-to-date .dpm is skipped) and a job that writes the
// catalogue once every task has succeeded (--dependency=afterok).
#pragma once

#include <string>
#include <vector>

#include "batch_list.h"
#include "dynpm/result.h"

namespace dynpm::cli {

struct SlurmRequest {
  std::string dynpm;                     // the program the jobs run (absolute)
  std::string out;                       // the output folder (absolute)
  std::vector<BatchInput> inputs;        // in task order
  std::vector<std::string> build_flags;  // passed on to every task ("--key-steps=paper", …)
  std::string partition, time, mem;      // "" when not given
  size_t max_running = 0;                // 0: no limit on tasks at once
  bool dry_run = false;
};

// Writes OUT/slurm/inputs.txt (the inputs, absolute, in task order: a task reads its line
// there, so a list or a glob that changes after submission cannot shift the tasks),
// OUT/slurm/build.sh and OUT/slurm/catalogue.sh, submits them with sbatch and prints the job
// ids; with dry_run prints the scripts and the sbatch commands and writes nothing.
Status submit_to_slurm(const SlurmRequest& request);

}  // namespace dynpm::cli
