// Huge pages (dynpm/core.h, cli/huge_pages.h): the tunable dynpm starts itself again with, and
// that the running tool has it where the kernel waits to be asked.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include "dynpm/core.h"
#include "dynpm_runs.h"
#include "fixtures.h"

namespace dynpm {
namespace {

constexpr const char* kMadvise = "always [madvise] never";

TEST(HugePages, OnlyWhereTheKernelWaitsToBeAsked) {
  EXPECT_EQ(tunables_with_huge_pages(nullptr, kMadvise), "glibc.malloc.hugetlb=1");
  EXPECT_EQ(tunables_with_huge_pages("", kMadvise), "glibc.malloc.hugetlb=1");
  EXPECT_FALSE(tunables_with_huge_pages(nullptr, "[always] madvise never"));
  EXPECT_FALSE(tunables_with_huge_pages(nullptr, "always madvise [never]"));
  EXPECT_FALSE(tunables_with_huge_pages(nullptr, ""));
}

TEST(HugePages, TheUsersTunablesAreKeptAndTheirChoiceWins) {
  EXPECT_EQ(tunables_with_huge_pages("glibc.malloc.arena_max=1", kMadvise),
            "glibc.malloc.arena_max=1:glibc.malloc.hugetlb=1");
  EXPECT_FALSE(tunables_with_huge_pages("glibc.malloc.hugetlb=0", kMadvise));  // the opt-out
  EXPECT_FALSE(tunables_with_huge_pages("glibc.malloc.arena_max=2:glibc.malloc.hugetlb=1",
                                        kMadvise));  // started again already: once only
}

std::string environment_of(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/environ", std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// The tool itself: a server (it waits) is looked at from outside, through /proc.
TEST(HugePages, TheToolRunsWithTheTunableWhereTheKernelWaitsToBeAsked) {
  std::ifstream mode_file("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string mode;
  if (!std::getline(mode_file, mode) || mode.find("[madvise]") == std::string::npos)
    GTEST_SKIP() << "the kernel's huge-page mode is '" << mode << "', not madvise";
  test::TempDir dir;
  ::unsetenv("GLIBC_TUNABLES");  // the tool adds it; in this process nothing reads it
  const pid_t pid = test::start_dynpm({"serve", dir.path().string(), "--port", "0"});
  bool seen = false;
  for (int i = 0; i < 200 && !seen; ++i) {  // up to 10 s on a loaded machine
    seen = environment_of(pid).find(std::string("GLIBC_TUNABLES=glibc.malloc.hugetlb=1") + '\0') !=
           std::string::npos;
    if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
  EXPECT_TRUE(seen) << "dynpm serve did not start again with glibc.malloc.hugetlb=1";
}

}  // namespace
}  // namespace dynpm
