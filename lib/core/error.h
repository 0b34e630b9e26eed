// Errors that reach the user as one line: "tool: error: <what>".
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace sss {

// Bad input or a failed operation. The message names the file (when there is one) and the
// problem, e.g. "env.exr: 12 NaN texels, first at (3, 7)".
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Control characters as \xNN: a message that quotes a file (a corrupt file's "name" may hold a
// newline or a terminal escape) stays one printable line.
inline std::string escapeControl(std::string_view text) {
  static const char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      out += {'\\', 'x', kHex[u >> 4], kHex[u & 15]};
    } else {
      out += c;
    }
  }
  return out;
}

// Throws Error("<path>: <problem>"), control characters escaped.
[[noreturn]] inline void fail(const std::string& path, const std::string& problem) {
  throw Error(escapeControl(path.empty() ? problem : path + ": " + problem));
}

}  // namespace sss
