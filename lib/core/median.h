// The median of a sample (the mean of the middle two for an even count; 0 for none): what the
// timings report, robust against a run the machine slowed.
#pragma once

#include <algorithm>
#include <vector>

namespace sss {

inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace sss
