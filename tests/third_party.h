// Running third-party tools from tests: Debian's meshio (python3-meshio) writes and reads mesh
// files that nobody on this project wrote. The project's test command installs it and sets
// DYNPM_REQUIRE_THIRD_PARTY=1, so there a missing tool fails the test instead of skipping it.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace dynpm::test {

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

inline CommandResult run_command(const std::string& command) {
  CommandResult result;
  std::FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return result;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

inline bool third_party_required() {
  const char* v = std::getenv("DYNPM_REQUIRE_THIRD_PARTY");
  return v && std::string(v) == "1";
}

// Debian's Python if it can import the module (meshio from python3-meshio, vtk from
// python3-vtk9), else an empty string.
inline std::string python_with(const std::string& module) {
  const std::string python = "/usr/bin/python3";
  return run_command(python + " -c 'import " + module + "'").exit_code == 0 ? python : "";
}
inline std::string meshio_python() {
  static const std::string python = python_with("meshio");
  return python;
}
// meshio writes Exodus II through netCDF4, a separate Debian package.
inline std::string meshio_exodus_python() {
  static const std::string python = python_with("meshio, netCDF4");
  return python;
}
inline std::string vtk_python() {
  static const std::string python = python_with("vtk");
  return python;
}

}  // namespace dynpm::test

// Skips (or, where third-party tools are required, fails) when a tool is missing.
#define DYNPM_REQUIRE_PYTHON(python, package)                                           \
  do {                                                                                  \
    if ((python).empty()) {                                                             \
      if (::dynpm::test::third_party_required()) FAIL() << package " is not installed"; \
      GTEST_SKIP() << package " is not installed";                                      \
    }                                                                                   \
  } while (0)
#define DYNPM_REQUIRE_MESHIO() \
  DYNPM_REQUIRE_PYTHON(::dynpm::test::meshio_python(), "python3-meshio")
#define DYNPM_REQUIRE_MESHIO_EXODUS()                         \
  DYNPM_REQUIRE_PYTHON(::dynpm::test::meshio_exodus_python(), \
                       "python3-meshio with "                 \
                       "python3-netcdf4")
#define DYNPM_REQUIRE_VTK() DYNPM_REQUIRE_PYTHON(::dynpm::test::vtk_python(), "python3-vtk9")
