// Numbers in messages and reports: printf formatting into a std::string.
#pragma once

#include <cstdio>
#include <string>

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

}  // namespace sss
