// Output files appear whole or not at all: write to a temporary name beside the target, rename
// when complete. A failure (exception, early return) removes the temporary file.
#pragma once

#include <string>

namespace sss {

class AtomicOutput {
 public:
  explicit AtomicOutput(std::string finalPath);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  // Where to write. Keeps the final name's extension (writers such as OpenImageIO pick the
  // format from it): "dir/.name.12345.tmp.exr".
  const std::string& tempPath() const { return temp_; }
  // Renames the temporary file to the final name; throws Error on failure.
  void commit();

 private:
  std::string final_;
  std::string temp_;
  bool committed_ = false;
};

// Writes `text` to `path` through an AtomicOutput (reports, JSON): the file appears whole or not
// at all. Throws Error naming the path.
void writeFileAtomically(const std::string& path, const std::string& text);

}  // namespace sss
