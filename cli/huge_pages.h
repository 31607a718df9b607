// For main(), first (dynpm/core.h "Huge pages"): starts the program again with glibc's
// glibc.malloc.hugetlb=1 where the kernel waits to be asked for huge pages. Returns, changing
// nothing, when it need not, or when the start fails. Header-only: bench/scale_bench.cpp does
// as the tool does.
#pragma once

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>

#include "dynpm/core.h"

namespace dynpm::cli {

inline void start_again_with_huge_pages(char** argv) {
#if defined(__GLIBC__) && defined(__linux__)
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string mode;
  if (!std::getline(in, mode)) return;
  const char* tunables = std::getenv("GLIBC_TUNABLES");
  const std::optional<std::string> before =
      tunables ? std::optional<std::string>(tunables) : std::nullopt;
  const auto with = tunables_with_huge_pages(tunables, mode);
  if (!with || ::setenv("GLIBC_TUNABLES", with->c_str(), 1) != 0) return;
  ::execv("/proc/self/exe", argv);
  // Not started again (no /proc, say): on as before, the environment as it was.
  if (before)
    ::setenv("GLIBC_TUNABLES", before->c_str(), 1);
  else
    ::unsetenv("GLIBC_TUNABLES");
#else
  (void)argv;
#endif
}

}  // namespace dynpm::cli
