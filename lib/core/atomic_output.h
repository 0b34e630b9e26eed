// Output files appear whole or not at all: write to a temporary name beside the target, rename
// when complete. A failure (exception, early return) removes the temporary file, and so does an
// interruption: every live temporary is in a registry that runTool's SIGINT/SIGTERM handler
// empties (core/tool.h) before the process exits.
//
// The temporary name is ".<stem>.<pid>.<random>.tmp.<ext>", created with O_EXCL when the
// AtomicOutput is constructed: two processes writing the same output (or a process reusing the
// pid of one killed with SIGKILL, whose temporary stays behind) never share or truncate each
// other's temporary, and the last rename wins with a whole file.
#pragma once

#include <string>

namespace sss {

class AtomicOutput {
 public:
  // Creates the (empty) temporary file; throws Error naming finalPath when it cannot.
  explicit AtomicOutput(std::string finalPath);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  // Where to write (the file exists, empty; writers open it with truncation). Keeps the final
  // name's extension, writers such as OpenImageIO pick the format from it:
  // "dir/.name.12345.9f3a61c2.tmp.exr".
  const std::string& tempPath() const { return temp_; }
  // Renames the temporary file to the final name; throws Error on failure.
  void commit();

 private:
  std::string final_;
  std::string temp_;
  int slot_ = -1;  // in the registry of live temporaries
  bool committed_ = false;
};

// Unlinks every live temporary file of this process. Async-signal-safe (unlink on fixed
// buffers): for signal handlers, which then _exit. Returns how many were registered.
int removeLiveTemporaries() noexcept;

// Writes `text` to `path` through an AtomicOutput (reports, JSON): the file appears whole or not
// at all. Throws Error naming the path.
void writeFileAtomically(const std::string& path, const std::string& text);

}  // namespace sss
