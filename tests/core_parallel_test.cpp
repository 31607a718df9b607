// core/parallel.h: every index once, deterministic parts, and a worker's exception carried to
// the caller instead of terminating the process.
#include <gtest/gtest.h>

#include <atomic>
#include <new>
#include <vector>

#include "core/parallel.h"

namespace dynpm {
namespace {

TEST(Parallel, EveryIndexOnceInContiguousParts) {
  for (unsigned threads : {1u, 2u, 4u}) {
    std::vector<int> seen(10001, 0);
    std::vector<std::pair<size_t, size_t>> ranges(7);
    parallel_for(seen.size(), 7, threads, [&](size_t begin, size_t end, size_t part) {
      ranges[part] = {begin, end};
      for (size_t i = begin; i < end; ++i) ++seen[i];
    });
    for (int s : seen) ASSERT_EQ(s, 1);
    for (size_t p = 0; p < ranges.size(); ++p) {  // the split does not depend on the threads
      EXPECT_EQ(ranges[p].first, std::min<size_t>(seen.size(), p * 1429));
      EXPECT_EQ(ranges[p].second, std::min<size_t>(seen.size(), (p + 1) * 1429));
    }
  }
}

TEST(Parallel, ChunksAreOnePerThreadOfAtLeast4096) {
  std::atomic<size_t> parts{0};
  parallel_for_chunks(10000, 8, [&](size_t, size_t, size_t) { ++parts; });
  EXPECT_EQ(parts, 2u);  // 10000 / 4096
  parts = 0;
  parallel_for_chunks(100, 8, [&](size_t begin, size_t end, size_t) {
    EXPECT_EQ(begin, 0u);
    EXPECT_EQ(end, 100u);
    ++parts;
  });
  EXPECT_EQ(parts, 1u);
}

TEST(Parallel, AWorkersBadAllocReachesTheCaller) {
  for (unsigned threads : {1u, 2u, 4u}) {
    std::atomic<size_t> done{0};
    EXPECT_THROW(parallel_for(64, 64, threads,
                              [&](size_t begin, size_t, size_t) {
                                if (begin == 5) throw std::bad_alloc();
                                ++done;
                              }),
                 std::bad_alloc)
        << threads << " threads";
    EXPECT_LT(done, 64u);
  }
}

}  // namespace
}  // namespace dynpm
