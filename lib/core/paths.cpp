#include "core/paths.h"

#include <filesystem>
#include <system_error>

#include "core/error.h"
#include "core/tool.h"

namespace sss {

namespace fs = std::filesystem;

namespace {

// The same file: one inode when both exist (any spelling, symlinks, hard links), else the same
// canonical path (an output not written yet).
bool sameFile(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::equivalent(a, b, ec)) return true;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return false;
  std::error_code ecA, ecB;
  const fs::path ca = fs::weakly_canonical(fs::absolute(a, ecA), ecA);
  const fs::path cb = fs::weakly_canonical(fs::absolute(b, ecB), ecB);
  return !ecA && !ecB && ca == cb;
}

}  // namespace

void checkInputFile(const std::string& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (!fs::exists(status)) return;
  if (fs::is_directory(status)) fail(path, "is a directory, not a file");
  if (!fs::is_regular_file(status)) fail(path, "not a regular file");
}

void checkOutputsAreNotInputs(const std::vector<ToolFile>& outputs,
                              const std::vector<ToolFile>& inputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const ToolFile& out = outputs[i];
    if (out.path.empty()) continue;
    for (const ToolFile& in : inputs) {
      std::error_code ec;
      if (in.path.empty() || !fs::exists(in.path, ec)) continue;
      if (sameFile(out.path, in.path)) {
        throw UsageError(out.name + " " + out.path + " is the same file as " + in.name + " (" +
                         in.path + "): refusing to overwrite an input");
      }
    }
    for (std::size_t j = 0; j < i; ++j) {
      const ToolFile& other = outputs[j];
      if (!other.path.empty() && sameFile(out.path, other.path)) {
        throw UsageError(out.name + " " + out.path + " is the same file as " + other.name + " (" +
                         other.path + "): two outputs cannot share a file");
      }
    }
  }
}

}  // namespace sss
