#include "core/atomic_output.h"

#include <fcntl.h>
#include <sys/random.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/error.h"

namespace sss {
namespace {

// The registry of live temporaries: fixed buffers, so that a signal handler can read them
// without allocating or locking. A slot is Free, Claimed (its path being written or its file
// being created: the handler leaves it alone, the file may be another process's) or Live.
enum SlotState : int { kFree = 0, kClaimed = 1, kLive = 2 };
constexpr int kSlots = 64;                // outputs open at once in one process
constexpr std::size_t kPathBytes = 4096;  // PATH_MAX on Linux, NUL included
static_assert(std::atomic<int>::is_always_lock_free);

struct Slot {
  std::atomic<int> state{kFree};
  char path[kPathBytes];
};
Slot gSlots[kSlots];

int claimSlot(const std::string& finalPath) {
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (gSlots[i].state.compare_exchange_strong(expected, kClaimed)) return i;
  }
  fail(finalPath, "cannot write (more than " + std::to_string(kSlots) + " outputs open at once)");
}

void releaseSlot(int slot) {
  gSlots[slot].state.store(kFree, std::memory_order_release);
}

// 32 random bits as 8 hex digits; the pid is in the name as well, the clock is the fallback.
std::string randomToken() {
  std::uint32_t bits = 0;
  if (::getrandom(&bits, sizeof bits, GRND_NONBLOCK) != static_cast<ssize_t>(sizeof bits)) {
    bits = static_cast<std::uint32_t>(std::chrono::steady_clock::now().time_since_epoch().count() *
                                      2654435761u);
  }
  char text[9];
  std::snprintf(text, sizeof text, "%08x", bits);
  return text;
}

std::string temporaryName(const std::filesystem::path& finalPath) {
  std::string name(1, '.');
  name.append(finalPath.stem().string()).append(".").append(std::to_string(::getpid()));
  name.append(".").append(randomToken()).append(".tmp").append(finalPath.extension().string());
  return (finalPath.parent_path() / name).string();
}

}  // namespace

AtomicOutput::AtomicOutput(std::string finalPath) : final_(std::move(finalPath)) {
  slot_ = claimSlot(final_);
  for (int attempt = 0;; ++attempt) {
    temp_ = temporaryName(final_);
    if (temp_.size() >= kPathBytes) {
      releaseSlot(slot_);
      fail(final_, "cannot write (the path is too long)");
    }
    std::memcpy(gSlots[slot_].path, temp_.c_str(), temp_.size() + 1);
    const int fd = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd >= 0) {
      gSlots[slot_].state.store(kLive, std::memory_order_release);
      ::close(fd);
      return;
    }
    if (errno != EEXIST || attempt == 100) {
      const std::string why = std::strerror(errno);
      releaseSlot(slot_);
      fail(final_, "cannot write (" + why + ")");
    }
  }
}

AtomicOutput::~AtomicOutput() {
  if (committed_) return;
  ::unlink(temp_.c_str());
  if (slot_ >= 0) releaseSlot(slot_);
}

void AtomicOutput::commit() {
  // The slot is released after the rename: a signal in between unlinks a name that is gone.
  if (std::rename(temp_.c_str(), final_.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    ::unlink(temp_.c_str());
    releaseSlot(slot_);
    slot_ = -1;
    fail(final_, "cannot write (" + why + ")");
  }
  releaseSlot(slot_);
  slot_ = -1;
  committed_ = true;
}

int removeLiveTemporaries() noexcept {
  int count = 0;
  for (Slot& slot : gSlots) {
    if (slot.state.load(std::memory_order_acquire) != kLive) continue;
    ::unlink(slot.path);
    ++count;
  }
  return count;
}

void writeFileAtomically(const std::string& path, const std::string& text) {
  AtomicOutput output(path);
  {
    std::ofstream file(output.tempPath(), std::ios::binary);
    file << text;
    if (!file.flush()) fail(path, "cannot write");
  }
  output.commit();
}

}  // namespace sss
