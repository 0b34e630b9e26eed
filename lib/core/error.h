// Errors that reach the user as one line: "tool: error: <what>".
#pragma once

#include <stdexcept>
#include <string>

namespace sss {

// Bad input or a failed operation. The message names the file (when there is one) and the
// problem, e.g. "env.exr: 12 NaN texels, first at (3, 7)".
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws Error("<path>: <problem>").
[[noreturn]] inline void fail(const std::string& path, const std::string& problem) {
  throw Error(path.empty() ? problem : path + ": " + problem);
}

}  // namespace sss
