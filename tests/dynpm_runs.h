// Running the dynpm binary from the tests that kill it or limit it (bad_input_test.cpp,
// atomic_outputs_test.cpp, core_memory_test.cpp), and the folders it leaves.
#pragma once

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace dynpm::test {

// The names in a folder, sorted.
inline std::vector<std::string> folder_entries(const std::filesystem::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

// "[a, b, c]", for comparing folder contents in one assertion.
inline std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return "[" + s + "]";
}

// The dynpm binary and these arguments, and the array execv() takes of them (pointing into
// `args`, which must outlive it).
inline std::vector<std::string> dynpm_command(const std::vector<std::string>& arguments) {
  std::vector<std::string> args = {DYNPM_CLI};
  args.insert(args.end(), arguments.begin(), arguments.end());
  return args;
}
inline std::vector<char*> argv_of(std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  return argv;
}

// dynpm with these arguments, started in the background (quiet); its process id.
inline pid_t start_dynpm(const std::vector<std::string>& arguments) {
  std::vector<std::string> args = dynpm_command(arguments);
  std::vector<char*> argv = argv_of(args);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, STDOUT_FILENO);
    ::dup2(null, STDERR_FILENO);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

}  // namespace dynpm::test
