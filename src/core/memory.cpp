#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#include "dynpm/core.h"
#include "pages.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace dynpm {
namespace {

constexpr uint64_t kUnknown = ~uint64_t{0};

// A "Name:  123 kB" line of a /proc file, in bytes.
uint64_t proc_kb_line(const char* path, const char* name) {
  std::FILE* f = std::fopen(path, "r");
  if (!f) return kUnknown;
  char line[256];
  uint64_t bytes = kUnknown;
  const size_t n = std::strlen(name);
  while (std::fgets(line, sizeof line, f))
    if (std::strncmp(line, name, n) == 0) {
      bytes = std::strtoull(line + n, nullptr, 10) << 10;
      break;
    }
  std::fclose(f);
  return bytes;
}

// The first number in a file ("max" and a missing file: unknown).
uint64_t file_number(const std::string& path) {
  std::ifstream in(path);
  std::string word;
  if (!(in >> word) || word.empty() || word[0] < '0' || word[0] > '9') return kUnknown;
  return std::strtoull(word.c_str(), nullptr, 10);
}

// The process's cgroup folder of one hierarchy, from /proc/self/cgroup: "0::/a/b" (v2,
// controllers "") or "4:memory:/a/b" (v1) → root + "/a/b"; "" when the process has none.
std::string cgroup_dir(const std::string& controllers, const std::string& root) {
  std::ifstream in("/proc/self/cgroup");
  for (std::string line; std::getline(in, line);) {
    const size_t a = line.find(':'), b = line.find(':', a + 1);
    if (a != std::string::npos && b != std::string::npos &&
        line.compare(a + 1, b - a - 1, controllers) == 0)
      return root + line.substr(b + 1);
  }
  return "";
}

uint64_t left_under(uint64_t limit, uint64_t used) {
  if (limit == kUnknown) return kUnknown;
  if (used == kUnknown) return limit;
  return used >= limit ? 0 : limit - used;
}

}  // namespace

void return_freed_arrays_to_the_system() {
#if defined(__GLIBC__)
  // Setting the threshold also turns off glibc's moving of it (mallopt(3)).
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
#endif
}

std::optional<std::string> tunables_with_huge_pages(const char* tunables,
                                                    std::string_view kernel_mode) {
  constexpr std::string_view kTunable = "glibc.malloc.hugetlb";
  if (kernel_mode.find("[madvise]") == std::string_view::npos) return std::nullopt;
  const std::string present = tunables ? tunables : "";
  if (present.find(kTunable) != std::string::npos) return std::nullopt;  // ours, or the user's
  return (present.empty() ? "" : present + ":") + std::string(kTunable) + "=1";
}

void release_free_heap() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

void release_pages(const void* begin, const void* end) {
#if defined(__linux__)
  static const uintptr_t page = static_cast<uintptr_t>(sysconf(_SC_PAGESIZE));
  const uintptr_t first = (reinterpret_cast<uintptr_t>(begin) + page - 1) / page * page;
  const uintptr_t last = reinterpret_cast<uintptr_t>(end) / page * page;
  if (first < last) madvise(reinterpret_cast<void*>(first), last - first, MADV_DONTNEED);
#else
  (void)begin, (void)end;
#endif
}

uint64_t available_memory_bytes() {
  uint64_t have = proc_kb_line("/proc/meminfo", "MemAvailable:");
  if (rlimit r{}; ::getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
    have = std::min(have, left_under(r.rlim_cur, proc_kb_line("/proc/self/status", "VmSize:")));
  if (const std::string dir = cgroup_dir("", "/sys/fs/cgroup"); !dir.empty())
    have = std::min(
        have, left_under(file_number(dir + "/memory.max"), file_number(dir + "/memory.current")));
  // cgroup v1: the process's own group, and the container's root group (which is where a
  // container's limit shows when the path is not visible inside it). "No limit" is a huge number.
  for (const std::string& dir :
       {cgroup_dir("memory", "/sys/fs/cgroup/memory"), std::string("/sys/fs/cgroup/memory")})
    if (!dir.empty())
      have = std::min(have, left_under(file_number(dir + "/memory.limit_in_bytes"),
                                       file_number(dir + "/memory.usage_in_bytes")));
  return have == kUnknown ? 0 : have;
}

}  // namespace dynpm
