// The sRGB transfer function (IEC 61966-2-1) between linear values and encoded ones in [0, 1].
#pragma once

#include <cmath>

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

}  // namespace sss
