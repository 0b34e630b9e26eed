#include "core/atomic_output.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/error.h"

namespace sss {

AtomicOutput::AtomicOutput(std::string finalPath) : final_(std::move(finalPath)) {
  namespace fs = std::filesystem;
  const fs::path p(final_);
  std::string name(1, '.');
  name.append(p.stem().string()).append(".").append(std::to_string(::getpid()));
  name.append(".tmp").append(p.extension().string());
  temp_ = (p.parent_path() / name).string();
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) std::remove(temp_.c_str());
}

void AtomicOutput::commit() {
  if (std::rename(temp_.c_str(), final_.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(temp_.c_str());
    fail(final_, "cannot write (" + why + ")");
  }
  committed_ = true;
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
