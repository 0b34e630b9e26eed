#include "core/memory.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/error.h"
#include "core/format.h"

namespace sss {
namespace {

constexpr std::uint64_t kUnknown = std::numeric_limits<std::uint64_t>::max();

// MemAvailable in bytes (the kernel's estimate of what can be allocated without swapping);
// sysconf's free pages when /proc/meminfo has none.
std::uint64_t memAvailable() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  std::uint64_t kb = 0;
  std::string unit;
  while (in >> key >> kb >> unit) {
    if (key == "MemAvailable:") return kb * 1024;
  }
  const long pages = ::sysconf(_SC_AVPHYS_PAGES), size = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && size > 0 ? std::uint64_t(pages) * std::uint64_t(size) : kUnknown;
}

std::uint64_t readNumber(const std::string& path) {
  std::ifstream in(path);
  std::uint64_t value = 0;
  return in >> value ? value : kUnknown;  // "max": no limit
}

// `key`'s value in a cgroup's memory.stat.
std::uint64_t statValue(const std::string& file, const std::string& key) {
  std::ifstream in(file);
  std::string name;
  std::uint64_t value = 0;
  while (in >> name >> value) {
    if (name == key) return value;
  }
  return 0;
}

// A container's limit less its usage, the reclaimable page cache (inactive files) not counted
// as used: cgroup v2 ("0::<path>" in /proc/self/cgroup) or v1 (the memory controller's line).
std::uint64_t cgroupAvailable() {
  std::ifstream in("/proc/self/cgroup");
  for (std::string line; std::getline(in, line);) {
    const bool v2 = line.rfind("0::", 0) == 0;
    const std::size_t at = line.find(":memory:");
    if (!v2 && at == std::string::npos) continue;
    const std::string path = v2 ? line.substr(3) : line.substr(at + 8);
    const std::string mount = v2 ? "/sys/fs/cgroup" : "/sys/fs/cgroup/memory";
    for (const std::string& dir : {mount + path, mount}) {  // a namespace shows its root
      const std::uint64_t limit = readNumber(dir + (v2 ? "/memory.max" : "/memory.limit_in_bytes"));
      const std::uint64_t usage =
          readNumber(dir + (v2 ? "/memory.current" : "/memory.usage_in_bytes"));
      if (limit == kUnknown || usage == kUnknown) continue;
      const std::uint64_t cache =
          statValue(dir + "/memory.stat", v2 ? "inactive_file" : "total_inactive_file");
      const std::uint64_t used = usage > cache ? usage - cache : 0;
      return limit > used ? limit - used : 0;
    }
  }
  return kUnknown;
}

std::uint64_t environmentLimit() {
  const char* value = std::getenv("SSS_MEMORY_LIMIT_MB");
  if (!value || !*value) return kUnknown;
  const std::string text(value);
  double mb = 0.0;
  const auto [at, error] = std::from_chars(text.data(), text.data() + text.size(), mb);
  if (error != std::errc() || at != text.data() + text.size() || !(mb > 0.0) ||
      !std::isfinite(mb)) {
    std::string problem = "'";
    problem.append(text).append("' is not a positive number of MiB");
    fail("SSS_MEMORY_LIMIT_MB", problem);
  }
  return static_cast<std::uint64_t>(std::min(mb * 1048576.0, 1.8e19));
}

std::string gigabytes(std::uint64_t bytes) {
  return format("%.3g GB", double(bytes) * 1e-9);
}

}  // namespace

AvailableMemory availableMemory() {
  AvailableMemory m{memAvailable(), "MemAvailable"};
  if (const std::uint64_t c = cgroupAvailable(); c < m.bytes) m = {c, "the cgroup's memory.max"};
  if (const std::uint64_t e = environmentLimit(); e < m.bytes) m = {e, "SSS_MEMORY_LIMIT_MB"};
  return m;
}

void checkMemoryNeed(const std::string& path, const std::string& task, std::uint64_t needBytes) {
  const AvailableMemory available = availableMemory();
  if (available.bytes == kUnknown || needBytes <= available.bytes) return;
  const std::string source =
      available.source == "MemAvailable" ? "" : " (" + available.source + ")";
  fail(path, task + " needs about " + gigabytes(needBytes) + ", " + gigabytes(available.bytes) +
                 " available" + source);
}

std::uint64_t peakResidentBytes() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return std::uint64_t(usage.ru_maxrss) * 1024;  // kilobytes on Linux
}

}  // namespace sss
