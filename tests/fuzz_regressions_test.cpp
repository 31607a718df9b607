// Replays the fuzz regressions (fuzz/regressions/<harness>/) through the harnesses' code paths
// (fuzz/targets.h) without libFuzzer: every input must be read without a crash or a failed check
// (an error Result is fine). Harnesses without regression files replay their seed corpus
// (fuzz/corpus/<harness>/) instead, so the test is never empty. A file named open-* is a finding
// whose fix has not landed yet: it is listed, not replayed (it would abort the test program);
// drop the prefix in the commit that fixes it. docs/RELIABILITY.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>
#include <vector>

#include "../fuzz/targets.h"

namespace {

namespace fs = std::filesystem;

struct Harness {
  const char* name;
  void (*run)(std::string_view);
  const char* folder = name;  // of fuzz/regressions/ and fuzz/corpus/
};

const Harness kHarnesses[] = {
    {"obj", dynpm::fuzz::run_obj},
    {"ply", dynpm::fuzz::run_ply},
    {"vtk", dynpm::fuzz::run_vtk},
    {"frd", dynpm::fuzz::run_frd},
    {"d3plot", dynpm::fuzz::run_d3plot},
    {"exodus", dynpm::fuzz::run_exodus},
    {"exodus_hdf5", dynpm::fuzz::run_exodus_hdf5, "exodus"},
    {"dpm", dynpm::fuzz::run_dpm},
};

std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> files;
  if (!fs::is_directory(dir)) return files;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file() && entry.path().filename().string().front() != '.')
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class FuzzRegressions : public ::testing::TestWithParam<Harness> {};

TEST_P(FuzzRegressions, ReplayWithoutCrash) {
  const Harness& h = GetParam();
  const fs::path root = fs::path(DYNPM_SOURCE_DIR) / "fuzz";
  const fs::path regressions = root / "regressions" / h.folder;
  ASSERT_TRUE(fs::is_directory(regressions)) << regressions << " is missing";
  std::vector<fs::path> inputs = files_in(regressions);
  const bool fixed_ones = std::any_of(inputs.begin(), inputs.end(), [](const fs::path& p) {
    return !p.filename().string().starts_with("open-");
  });
  if (!fixed_ones) {
    const std::vector<fs::path> seeds = files_in(root / "corpus" / h.folder);
    inputs.insert(inputs.end(), seeds.begin(), seeds.end());
  }
  ASSERT_FALSE(inputs.empty()) << "no regression or seed files for " << h.name;
  for (const fs::path& input : inputs) {
    if (input.filename().string().starts_with("open-")) {
      std::cout << "[ open     ] " << input.string() << " (known finding, not replayed)\n";
      continue;
    }
    SCOPED_TRACE(input.string());
    h.run(slurp(input));  // a crash or a failed check aborts the test program
  }
}

INSTANTIATE_TEST_SUITE_P(FuzzHarnesses, FuzzRegressions, ::testing::ValuesIn(kHarnesses),
                         [](const ::testing::TestParamInfo<Harness>& param_info) {
                           return std::string(param_info.param.name);
                         });

}  // namespace
