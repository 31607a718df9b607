#include "batch_slurm.h"

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "dynpm/core.h"
#include "processes.h"

namespace dynpm::cli {
namespace {

std::string joined_for_shell(const std::vector<std::string>& words) {
  std::string line;
  for (const std::string& w : words) line += (line.empty() ? "" : " ") + shell_quoted(w);
  return line;
}

// The array task: variant SLURM_ARRAY_TASK_ID of the frozen list. '--jobs 1': the task has the
// CPUs Slurm gave it, which the build uses as its threads unless --threads was given.
std::string array_script(const SlurmRequest& r, const std::string& frozen_list) {
  std::vector<std::string> command = {r.dynpm, "batch", frozen_list, "--out", r.out};
  command.insert(command.end(), r.build_flags.begin(), r.build_flags.end());
  return "#!/bin/sh\n"
         "# dynpm batch: one variant per array task (written by 'dynpm batch --slurm').\n"
         "set -eu\n"
         "exec " +
         joined_for_shell(command) + " --task \"$SLURM_ARRAY_TASK_ID\"\n";
}

std::string catalogue_script(const SlurmRequest& r) {
  return "#!/bin/sh\n"
         "# dynpm batch: the catalogue, once every build has succeeded.\n"
         "set -eu\n"
         "exec " +
         joined_for_shell({r.dynpm, "catalogue", r.out}) + "\n";
}

// The options every job of the batch shares.
std::vector<std::string> common_options(const SlurmRequest& r) {
  std::vector<std::string> options;
  if (!r.partition.empty()) options.push_back("--partition=" + r.partition);
  if (!r.time.empty()) options.push_back("--time=" + r.time);
  if (!r.mem.empty()) options.push_back("--mem=" + r.mem);
  return options;
}

// "123" or "123;cluster" (sbatch --parsable) → "123".
Result<std::string> job_id(const std::string& parsable) {
  std::string id = parsable.substr(0, parsable.find_first_of(";\n"));
  if (id.empty() || id.find_first_not_of("0123456789") != std::string::npos)
    return Status::error("sbatch printed '" + parsable + "', not a job id");
  return id;
}

}  // namespace

Status submit_to_slurm(const SlurmRequest& r) {
  // Slurm reads '%' in --output as a pattern.
  if (r.out.find('%') != std::string::npos)
    return Status::error(r.out + ": a folder with '%' in its name cannot hold Slurm's logs");
  const std::filesystem::path slurm = std::filesystem::path(r.out) / "slurm";
  const std::string frozen_list = (slurm / "inputs.txt").string();
  const std::string build_sh = (slurm / "build.sh").string();
  const std::string catalogue_sh = (slurm / "catalogue.sh").string();
  const std::string logs = (std::filesystem::path(r.out) / "logs").string();
  std::string array = "--array=0-" + std::to_string(r.inputs.size() - 1);
  if (r.max_running > 0) array += "%" + std::to_string(r.max_running);

  std::vector<std::string> submit_array = {"sbatch", "--parsable", "--job-name=dynpm-build", array,
                                           "--output=" + logs + "/slurm-%A_%a.out"};
  const std::vector<std::string> common = common_options(r);
  submit_array.insert(submit_array.end(), common.begin(), common.end());
  submit_array.push_back(build_sh);
  std::vector<std::string> submit_catalogue = {"sbatch", "--parsable", "--job-name=dynpm-catalogue",
                                               "--output=" + logs + "/slurm-%j.out"};
  submit_catalogue.insert(submit_catalogue.end(), common.begin(), common.end());
  const std::string dependency = "--dependency=afterok:";

  std::string frozen;
  for (const BatchInput& input : r.inputs)
    frozen += std::filesystem::absolute(input.path).lexically_normal().string() + "\n";

  if (r.dry_run) {
    std::cout << "# " << frozen_list << "\n"
              << frozen << "# " << build_sh << "\n"
              << array_script(r, frozen_list) << "# " << catalogue_sh << "\n"
              << catalogue_script(r) << "# submitted with\n"
              << joined_for_shell(submit_array) << "\n";
    submit_catalogue.push_back(dependency + "ARRAY_JOB_ID");
    submit_catalogue.push_back(catalogue_sh);
    std::cout << joined_for_shell(submit_catalogue) << "\n";
    return {};
  }
  for (const std::string& folder : {slurm.string(), logs}) {  // Slurm writes no log into a
    std::error_code ec;                                       // folder that is not there
    std::filesystem::create_directories(folder, ec);
    if (ec) return Status::error(folder + ": cannot make the folder: " + ec.message());
  }
  DYNPM_RETURN_IF_ERROR(write_file_atomically(frozen_list, frozen));
  DYNPM_RETURN_IF_ERROR(write_file_atomically(build_sh, array_script(r, frozen_list)));
  DYNPM_RETURN_IF_ERROR(write_file_atomically(catalogue_sh, catalogue_script(r)));

  auto array_out = run_and_capture(submit_array);
  if (!array_out) return array_out.status();
  auto array_id = job_id(*array_out);
  if (!array_id) return array_id.status();
  submit_catalogue.push_back(dependency + *array_id);
  submit_catalogue.push_back(catalogue_sh);
  auto catalogue_out = run_and_capture(submit_catalogue);
  if (!catalogue_out)
    return Status::error(catalogue_out.message() + " (the builds, job " + *array_id +
                         ", were submitted)");
  auto catalogue_id = job_id(*catalogue_out);
  if (!catalogue_id) return catalogue_id.status();
  std::cout << "array job " << *array_id << ": " << r.inputs.size() << " builds\n"
            << "catalogue job " << *catalogue_id << ": writes "
            << (std::filesystem::path(r.out) / "index.json").string() << " after them\n";
  return {};
}

}  // namespace dynpm::cli
