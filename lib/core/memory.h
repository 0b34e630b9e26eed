// Memory the process may still use, and its peak so far: for refusing up front work that would
// not fit (a bake's estimate against what is available), and for benchmarks.
#pragma once

#include <cstdint>
#include <string>

namespace sss {

struct AvailableMemory {
  std::uint64_t bytes = 0;
  // What bounds it: "MemAvailable" (/proc/meminfo), "the cgroup's memory.max" (a container's
  // limit less its usage) or "SSS_MEMORY_LIMIT_MB".
  std::string source;
};

// The least of /proc/meminfo's MemAvailable, the cgroup v2 limit less the cgroup's usage, and
// the environment variable SSS_MEMORY_LIMIT_MB (a cap in MiB, for tests and shared machines).
// Throws Error when SSS_MEMORY_LIMIT_MB is set but not a positive number.
AvailableMemory availableMemory();

// Throws Error("<path>: <task> needs about X GB, Y GB available") when needBytes exceeds
// availableMemory() (GB = 10^9 bytes, 3 significant digits; the source named when it is the
// environment variable or the cgroup).
void checkMemoryNeed(const std::string& path, const std::string& task, std::uint64_t needBytes);

// The process's peak resident set size so far (getrusage), in bytes.
std::uint64_t peakResidentBytes();

}  // namespace sss
