#include "image/oiio_file.h"

#include <dlfcn.h>

#include <atomic>
#include <filesystem>
#include <vector>

#include "core/error.h"
#include "image/oiio_module.h"

namespace sss {
namespace {

std::atomic<bool> gLoaded{false};

// Where an installed tool finds the module: SSS_OIIO_MODULE_DIR, relative to the executable's
// folder (bin/ -> lib/sss-tools/, set by lib/image/CMakeLists.txt); then the bare name, which
// the dynamic loader looks up in the executable's RUNPATH (the build tree's module folder in
// build-tree programs) and LD_LIBRARY_PATH.
std::vector<std::string> moduleCandidates() {
  std::vector<std::string> candidates;
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    candidates.push_back(
        (exe.parent_path() / SSS_OIIO_MODULE_DIR / kOiioModuleFile).lexically_normal().string());
  }
  candidates.push_back(kOiioModuleFile);
  return candidates;
}

// Loads the module once per process; the error of a failed load, or "".
const OiioModule* loadModule(std::string& error) {
  void* handle = nullptr;
  for (const std::string& candidate : moduleCandidates()) {
    handle = dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle) break;
    const char* why = dlerror();
    if (error.empty() && why) error = why;
  }
  if (!handle) return nullptr;
  using Entry = const OiioModule* (*)();
  auto entry = reinterpret_cast<Entry>(dlsym(handle, kOiioModuleEntry));
  const OiioModule* module = entry ? entry() : nullptr;
  if (!module || module->abi != kOiioModuleAbi) {
    error = std::string(kOiioModuleFile) + " is from another build (interface differs)";
    return nullptr;
  }
  gLoaded = true;
  return module;
}

const OiioModule& module(const std::string& path) {
  static std::string error;
  static const OiioModule* const loaded = loadModule(error);
  if (!loaded) {
    fail(path, "this format needs OpenImageIO, whose module could not be loaded (" + error + ")");
  }
  return *loaded;
}

}  // namespace

DecodedImage readWithOiio(const std::string& path) {
  return module(path).read(path);
}

void writeWithOiio(const std::string& path, const PixelsToWrite& pixels) {
  module(path).write(path, pixels);
}

bool oiioLoaded() {
  return gLoaded;
}

}  // namespace sss
