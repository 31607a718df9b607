#include "outputs.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <set>

#include "dynpm/core.h"

namespace dynpm::cli {

Status check_output_folder(const std::string& output) {
  std::error_code ec;
  if (std::filesystem::is_directory(output, ec))
    return Status::error(output + ": is a directory; give a file name");
  const std::filesystem::path folder = std::filesystem::path(output).parent_path();
  if (!folder.empty() && !std::filesystem::is_directory(folder, ec))
    return Status::error(output + ": no folder '" + folder.string() + "' to write into");
  return {};
}

StagedOutputs::~StagedOutputs() {
  for (const auto& [staged, target] : files_) std::remove(staged.c_str());
}

std::string StagedOutputs::stage(const std::string& path) {
  const std::filesystem::path target(path);
  std::filesystem::path staged = target;
  staged.replace_filename(target.stem().string() + ".tmp-" + std::to_string(::getpid()) +
                          target.extension().string());
  files_.emplace_back(staged.string(), path);
  return staged.string();
}

Status StagedOutputs::commit() {
  // What killed runs left beside the targets: one listing of each folder for all of them (one
  // per file made 10,000 steps quadratic).
  std::vector<std::string> targets;
  targets.reserve(files_.size());
  for (const auto& [staged, target] : files_) targets.push_back(target);
  remove_stale_temporaries(targets);
  for (const auto& [staged, target] : files_)
    if (std::rename(staged.c_str(), target.c_str()) != 0)
      return Status::error(target +
                           ": cannot rename the finished file into place: " + std::strerror(errno));
  // Once per folder, not per file: an fsync each costs milliseconds.
  std::set<std::filesystem::path> folders;
  for (const auto& [staged, target] : files_)
    if (folders.insert(std::filesystem::path(target).parent_path()).second)
      sync_directory_of(target);
  files_.clear();
  return {};
}

}  // namespace dynpm::cli
