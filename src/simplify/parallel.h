// A parallel for over [0, n) in contiguous chunks, one std::thread each; deterministic as long
// as the body writes only to its own indices.
#pragma once

#include <algorithm>
#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace dynpm::simplification {

inline unsigned thread_count(unsigned requested) {
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  return requested == 0 ? hw : requested;
}

// body(begin, end, thread_index)
template <class Body>
void parallel_for(size_t n, unsigned threads, Body&& body) {
  threads =
      static_cast<unsigned>(std::min<size_t>(std::max(1u, threads), std::max<size_t>(n / 4096, 1)));
  if (threads <= 1) {
    body(size_t{0}, n, 0u);
    return;
  }
  std::vector<std::thread> pool;
  pool.reserve(threads);  // before any thread runs: a throw later would leave them unjoined
  // An exception in a worker (std::bad_alloc) is rethrown here, not std::terminate.
  std::vector<std::exception_ptr> failed(threads);
  const size_t chunk = (n + threads - 1) / threads;
  for (unsigned i = 0; i < threads; ++i) {
    const size_t begin = std::min(n, i * chunk), end = std::min(n, begin + chunk);
    auto work = [&body, &failed, begin, end, i] {
      try {
        body(begin, end, i);
      } catch (...) {
        failed[i] = std::current_exception();
      }
    };
    try {
      pool.emplace_back(work);
    } catch (...) {  // no thread to be had (memory, limits): do it here
      work();
    }
  }
  for (std::thread& t : pool) t.join();
  for (const std::exception_ptr& e : failed)
    if (e) std::rethrow_exception(e);
}

}  // namespace dynpm::simplification
