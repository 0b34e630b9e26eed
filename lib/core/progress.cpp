#include "core/progress.h"

#include <unistd.h>

#include <chrono>
#include <cstdio>

namespace sss {
namespace {
long long nowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}
}  // namespace

Progress::Progress(std::string label, std::size_t total, bool quiet)
    : label_(std::move(label)), total_(total), enabled_(!quiet && ::isatty(STDERR_FILENO)) {}

Progress::~Progress() {
  finish();
}

void Progress::advance(std::size_t n) {
  const std::size_t done = done_.fetch_add(n) + n;
  if (!enabled_) return;
  const long long now = nowNs();
  long long last = lastDrawNs_.load();
  if (now - last < 100'000'000 || !lastDrawNs_.compare_exchange_strong(last, now)) return;
  std::lock_guard lock(mutex_);
  draw(done, false);
}

void Progress::finish() {
  if (!enabled_ || finished_) return;
  std::lock_guard lock(mutex_);
  finished_ = true;
  draw(total_, true);
}

void Progress::draw(std::size_t done, bool final) {
  const double f = total_ ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
  const int width = 30, filled = static_cast<int>(f * width + 0.5);
  std::fprintf(stderr, "\r%-24s [%.*s%*s] %5.1f%%", label_.c_str(), filled,
               "##############################", width - filled, "", 100.0 * f);
  if (final) std::fputc('\n', stderr);
  std::fflush(stderr);
}

}  // namespace sss
