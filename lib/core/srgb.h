// The sRGB transfer function (IEC 61966-2-1) between linear values and encoded ones in [0, 1].
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace sss {

inline float srgbToLinear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// Clamps to [0, 1] first (NaN gives 0).
inline float linearToSrgb(float linear) {
  if (!(linear > 0.0f)) return 0.0f;
  if (linear >= 1.0f) return 1.0f;
  return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

// lround(255 linearToSrgb(linear)) without a pow per value: the byte is the number of
// thresholds t_1 < ... < t_255 at or below `linear`, t_b the least float whose encoding rounds
// to b (found once by bisection over the ordered bit patterns of non-negative floats).
inline std::uint8_t linearToSrgbByte(float linear) {
  static const std::array<float, 255> thresholds = [] {
    std::array<float, 255> t{};
    auto byteOf = [](std::uint32_t bits) {
      float v;
      std::memcpy(&v, &bits, sizeof v);
      return std::lround(255.0f * linearToSrgb(v));
    };
    for (int b = 1; b <= 255; ++b) {
      std::uint32_t lo = 0, hi = 0x3f800000;  // 0 and 1.0f: byteOf(hi) = 255
      while (lo < hi) {
        const std::uint32_t mid = lo + (hi - lo) / 2;
        if (byteOf(mid) >= b)
          hi = mid;
        else
          lo = mid + 1;
      }
      std::memcpy(&t[b - 1], &lo, sizeof lo);
    }
    return t;
  }();
  if (!(linear > 0.0f)) return 0;
  int count = 0;
  for (int step = 128; step > 0; step /= 2) {
    if (count + step <= 255 && thresholds[count + step - 1] <= linear) count += step;
  }
  return static_cast<std::uint8_t>(count);
}

}  // namespace sss
