// The inputs of 'dynpm batch': a list file read into one variant per input, each with the name
// of its .dpm, and whether that .dpm is already up to date.
#pragma once

#include <string>
#include <vector>

#include "dynpm/result.h"

namespace dynpm::cli {

struct BatchInput {
  std::string path;  // as found: relative lines resolved against the list's folder
  size_t line = 0;   // of the list, from 1
  std::string name;  // variant_name(path): the .dpm is OUT/<name>.dpm
};

// A file's variant name: its name without folder and extension, and without a compression
// suffix first ("runs/v07.frd.gz" → "v07").
std::string variant_name(const std::string& path);

// One input a line; blank lines and lines starting with '#' are skipped, surrounding spaces
// trimmed. A line may be a glob (each match is one variant; a glob that matches nothing is an
// error naming its line). Two inputs of one name are refused, naming both lines.
Result<std::vector<BatchInput>> read_batch_list(const std::string& list);

// True when `dpm` exists and was written after `input` was last changed.
bool is_up_to_date(const std::string& dpm, const std::string& input);

}  // namespace dynpm::cli
