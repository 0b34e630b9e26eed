// Wall-clock stage timing for reports (--json) and benchmarks.
#pragma once

#include <chrono>
#include <ctime>

namespace sss {

class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  double milliseconds() const { return seconds() * 1e3; }
  void restart() { start_ = std::chrono::steady_clock::now(); }
  // The seconds since the start, and a new start: one stage's time after another's.
  double lap() {
    const auto now = std::chrono::steady_clock::now();
    const double s = std::chrono::duration<double>(now - start_).count();
    start_ = now;
    return s;
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

// CPU time of the whole process so far, all threads together (std::clock): on a shared machine
// the stable measure beside wall time.
inline double processCpuMilliseconds() {
  return 1e3 * static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

}  // namespace sss
