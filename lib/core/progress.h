// A progress bar on stderr for long stages. Silent when quiet or when stderr is not a TTY.
#pragma once

#include <atomic>
#include <cstddef>
#include <mutex>
#include <string>

namespace sss {

class Progress {
 public:
  Progress(std::string label, std::size_t total, bool quiet);
  ~Progress();
  // Thread-safe; redraws at most ~10 times a second.
  void advance(std::size_t n = 1);
  void finish();

 private:
  void draw(std::size_t done, bool final);

  std::string label_;
  std::size_t total_;
  bool enabled_;
  bool finished_ = false;
  std::atomic<std::size_t> done_{0};
  std::atomic<long long> lastDrawNs_{0};
  std::mutex mutex_;
};

}  // namespace sss
