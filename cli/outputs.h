// Where a verb writes: the output's folder checked before the work, and the files of one output
// written under temporary names and renamed into place together.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "dynpm/result.h"

namespace dynpm::cli {

// Before a long run: an error if `output` (a file or a step pattern) is a folder or its folder
// does not exist, so that the work is not lost at the end.
Status check_output_folder(const std::string& output);

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

}  // namespace dynpm::cli
