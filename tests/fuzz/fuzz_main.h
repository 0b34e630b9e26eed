// The libFuzzer entry point of a target: each <target>_fuzz.cpp is SSS_FUZZ_TARGET("<target>").
// An sss::Error is the expected answer to bad input, as one printable line; every other exception
// escapes, and libFuzzer reports it (with the input saved) like a crash, as it does an error
// message holding a control character.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>

#include "core/error.h"
#include "fuzz_readers.h"

namespace sss::fuzz {

// One scratch directory per fuzzing process (parallel jobs and targets stay apart), removed at
// normal exit.
class FuzzDir {
 public:
  FuzzDir()
      : dir_(std::filesystem::temp_directory_path() / ("sss-fuzz-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(dir_);
  }
  ~FuzzDir() {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  std::string path() const { return dir_.string(); }

 private:
  std::filesystem::path dir_;
};

inline bool isControl(char c) {
  return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
}

inline int fuzzOne(std::string_view target, const std::uint8_t* data, std::size_t size) {
  static const FuzzDir dir;
  try {
    readInput(target, std::string_view(reinterpret_cast<const char*>(data), size), dir.path());
  } catch (const Error& e) {
    // The tools print it as their one error line: a newline or a terminal escape from the file
    // must not get through.
    const std::string_view message = e.what();
    if (std::any_of(message.begin(), message.end(), [](char c) { return isControl(c); })) {
      std::fprintf(stderr, "error message with a control character: %s\n",
                   escapeControl(message.substr(0, 200)).c_str());
      std::abort();
    }
  }
  return 0;
}

}  // namespace sss::fuzz

#define SSS_FUZZ_TARGET(name)                                                         \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { \
    return sss::fuzz::fuzzOne(name, data, size);                                      \
  }
