// The one parallel loop of the library (simplify rates edges and builds quadrics with it, eval
// measures its sample jobs with it). Internal: modules include it as "core/parallel.h".
//
// [0, n) is cut into `parts` contiguous ranges of equal size (the last may be shorter or
// empty); body(begin, end, part) runs once for each, on up to `threads` threads (the caller's
// own included) that take the next part as they become free. The result is deterministic as
// long as the body writes only to its own indices or to its own part's slot. An exception in
// the body (std::bad_alloc) stops the handing out of parts and is rethrown in the caller, never
// std::terminate.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace dynpm {

// 0 means one thread per hardware thread.
inline unsigned thread_count(unsigned requested) {
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  return requested == 0 ? hw : requested;
}

template <class Body>
void parallel_for(size_t n, size_t parts, unsigned threads, Body&& body) {
  parts = std::max<size_t>(parts, 1);
  threads = static_cast<unsigned>(std::clamp<size_t>(threads, 1, parts));
  const size_t chunk = (n + parts - 1) / parts;
  if (threads == 1) {
    for (size_t p = 0; p < parts; ++p) {
      const size_t begin = std::min(n, p * chunk);
      body(begin, std::min(n, begin + chunk), p);
    }
    return;
  }
  std::atomic<size_t> next{0};
  std::exception_ptr failed;
  std::mutex failed_mutex;
  auto worker = [&] {
    for (size_t p = next++; p < parts; p = next++) {
      const size_t begin = std::min(n, p * chunk);
      try {
        body(begin, std::min(n, begin + chunk), p);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failed_mutex);
        if (!failed) failed = std::current_exception();
        next = parts;  // no more parts: the caller will rethrow
      }
    }
  };
  std::vector<std::thread> pool;
  try {
    pool.reserve(threads - 1);
    for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  } catch (...) {  // no thread to be had (memory, limits): the threads started and this one work
  }
  worker();
  for (std::thread& t : pool) t.join();
  if (failed) std::rethrow_exception(failed);
}

// The simplifier's split: one contiguous part per thread, and no more threads than parts of
// 4096 indices.
template <class Body>
void parallel_for_chunks(size_t n, unsigned threads, Body&& body) {
  const size_t parts = std::min<size_t>(std::max(1u, threads), std::max<size_t>(n / 4096, 1));
  parallel_for(n, parts, static_cast<unsigned>(parts), std::forward<Body>(body));
}

}  // namespace dynpm
