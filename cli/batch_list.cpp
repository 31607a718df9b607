#include "batch_list.h"

#include <filesystem>
#include <fstream>
#include <map>

#include "dynpm/io.h"

namespace dynpm::cli {

std::string variant_name(const std::string& path) {
  std::filesystem::path name = std::filesystem::path(path).filename();
  for (const char* compressed : {".gz", ".xz", ".zst", ".bz2"})
    if (name.extension() == compressed) name = name.stem();
  return name.stem().string();
}

Result<std::vector<BatchInput>> read_batch_list(const std::string& list) {
  std::ifstream in(list);
  if (!in) return Status::error(list + ": cannot read the list of inputs");
  const std::filesystem::path folder = std::filesystem::path(list).parent_path();
  std::vector<BatchInput> inputs;
  std::map<std::string, size_t> by_name;  // name → index in inputs
  size_t number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    const size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const std::string text = line.substr(first, line.find_last_not_of(" \t\r") + 1 - first);
    std::filesystem::path path(text);
    if (path.is_relative()) path = folder / path;
    const std::string where = list + ":" + std::to_string(number) + ": ";
    // A plain name is kept even when missing: its build fails with the reader's message and
    // the others go on. A glob must match.
    std::vector<std::string> matches = {path.string()};
    if (text.find_first_of("*?[") != std::string::npos) {
      auto found = expand_inputs(matches);
      if (!found) return Status::error(where + found.message());
      matches = std::move(*found);
    }
    for (const std::string& match : matches) {
      BatchInput input{match, number, variant_name(match)};
      if (input.name.empty()) return Status::error(where + match + ": no file name");
      auto [it, fresh] = by_name.emplace(input.name, inputs.size());
      if (!fresh) {
        const BatchInput& other = inputs[it->second];
        return Status::error(where + match + " and line " + std::to_string(other.line) + " (" +
                             other.path + ") would both write " + input.name +
                             ".dpm; rename one of them");
      }
      inputs.push_back(std::move(input));
    }
  }
  if (inputs.empty()) return Status::error(list + ": names no input");
  return inputs;
}

bool is_up_to_date(const std::string& dpm, const std::string& input) {
  std::error_code ec_out, ec_in;
  const auto written = std::filesystem::last_write_time(dpm, ec_out);
  const auto changed = std::filesystem::last_write_time(input, ec_in);
  return !ec_out && !ec_in && written > changed;
}

}  // namespace dynpm::cli
