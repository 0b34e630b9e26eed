// Numbers in messages and reports: printf formatting into a std::string; and numbers in files'
// text (header comments, keys): the shortest decimal that reads back to the same double, and its
// strict reader.
#pragma once

#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>

namespace sss {

// format("%.3g mm", 1.5) == "1.5 mm". One numeric argument; the format must take exactly one.
inline std::string format(const char* printfFormat, double value) {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, printfFormat, value);
  return buffer;
}

// A fraction as a percentage with three significant digits: 0.0123 -> "1.23%".
inline std::string percent(double fraction) {
  return format("%.3g%%", 100.0 * fraction);
}

// The shortest text that reads back to the same double (std::to_chars).
inline std::string shortestDecimal(double x) {
  char buffer[32];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, r.ptr);
}

// `text` whole as a finite double (std::from_chars: no spaces, no sign but '-'); false otherwise.
inline bool parseDecimal(std::string_view text, double& x) {
  const auto r = std::from_chars(text.data(), text.data() + text.size(), x);
  return r.ec == std::errc() && r.ptr == text.data() + text.size() && std::isfinite(x);
}

}  // namespace sss
