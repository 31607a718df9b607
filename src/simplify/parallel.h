// A parallel for over [0, n) in contiguous chunks, one std::thread each; deterministic as long
// as the body writes only to its own indices.
#pragma once

#include <algorithm>
#include <cstddef>
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
  const size_t chunk = (n + threads - 1) / threads;
  for (unsigned i = 0; i < threads; ++i) {
    const size_t begin = std::min(n, i * chunk), end = std::min(n, begin + chunk);
    pool.emplace_back([&body, begin, end, i] { body(begin, end, i); });
  }
  for (std::thread& t : pool) t.join();
}

}  // namespace dynpm::simplification
