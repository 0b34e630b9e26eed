// A static-partition parallel loop. The work split depends only on n and the grain, never on
// the thread count, so per-item results (and per-item random seeds) are identical for any
// number of threads.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace sss {

inline int defaultThreadCount() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

// Calls body(begin, end) on chunks of [0, n) of at most `grain` items, from `threads` threads
// (<= 0: all cores). The first exception thrown by a body is rethrown here.
template <class Body>
void parallelFor(std::size_t n, int threads, std::size_t grain, Body&& body) {
  if (n == 0) return;
  grain = std::max<std::size_t>(grain, 1);
  const std::size_t chunks = (n + grain - 1) / grain;
  const int t = static_cast<int>(
      std::min<std::size_t>(chunks, threads <= 0 ? defaultThreadCount() : threads));
  std::atomic<std::size_t> next{0};
  std::exception_ptr error;
  std::mutex errorMutex;
  auto worker = [&] {
    for (std::size_t c; (c = next.fetch_add(1)) < chunks;) {
      try {
        body(c * grain, std::min(n, (c + 1) * grain));
      } catch (...) {
        std::lock_guard lock(errorMutex);
        if (!error) error = std::current_exception();
        next = chunks;
      }
    }
  };
  if (t <= 1) {
    worker();
  } else {
    std::vector<std::thread> pool;
    for (int i = 0; i < t - 1; ++i) pool.emplace_back(worker);
    worker();
    for (auto& th : pool) th.join();
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace sss
