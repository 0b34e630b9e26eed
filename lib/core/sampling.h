// Low-discrepancy points and direction sampling shared by the bake's visibility rays and the
// Monte Carlo walks; each sampler stands beside its pdf (after pbrt-v4's util/sampling.h).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/vec3.hpp>

namespace sss {

// Van der Corput radical inverse in base 2 of i, in [0, 1) with 24 bits.
inline float radicalInverse2(uint32_t i) {
  i = (i << 16u) | (i >> 16u);
  i = ((i & 0x55555555u) << 1u) | ((i & 0xAAAAAAAAu) >> 1u);
  i = ((i & 0x33333333u) << 2u) | ((i & 0xCCCCCCCCu) >> 2u);
  i = ((i & 0x0F0F0F0Fu) << 4u) | ((i & 0xF0F0F0F0u) >> 4u);
  i = ((i & 0x00FF00FFu) << 8u) | ((i & 0xFF00FF00u) >> 8u);
  return static_cast<float>(i >> 8) * 0x1p-24f;
}

// Wraps into [0, 1) without ever returning 1 (float rounding of x - floor(x)).
inline float wrap01(float x) {
  return std::min(x - std::floor(x), 0x1.fffffep-1f);
}

// Point i of an n-point Hammersley set, rotated by (r0, r1) on the torus (Cranley-Patterson).
inline void hammersley(uint32_t i, uint32_t n, float r0, float r1, float& u1, float& u2) {
  u1 = wrap01((static_cast<float>(i) + 0.5f) / static_cast<float>(n) + r0);
  u2 = wrap01(radicalInverse2(i) + r1);
}

// Orthonormal basis (t, b) completing unit n (Duff et al. 2017, "Building an Orthonormal Basis,
// Revisited").
inline void orthonormalBasis(const glm::vec3& n, glm::vec3& t, glm::vec3& b) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = glm::vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
  b = glm::vec3(c, sign + n.y * n.y * a, -n.y);
}

// Cosine-weighted direction about +Z from the concentric disk mapping (Shirley & Chiu 1997),
// which keeps the stratification of (u1, u2). pdf: cosineHemispherePdf.
inline glm::vec3 sampleCosineHemisphereConcentric(float u1, float u2) {
  const float a = 2.0f * u1 - 1.0f, b = 2.0f * u2 - 1.0f;
  float r = 0.0f, phi = 0.0f;
  if (a != 0.0f || b != 0.0f) {
    if (std::abs(a) > std::abs(b)) {
      r = a;
      phi = static_cast<float>(M_PI / 4.0) * (b / a);
    } else {
      r = b;
      phi = static_cast<float>(M_PI / 2.0) - static_cast<float>(M_PI / 4.0) * (a / b);
    }
  }
  const float x = r * std::cos(phi), y = r * std::sin(phi);
  return glm::vec3(x, y, std::sqrt(std::max(0.0f, 1.0f - x * x - y * y)));
}

// Density of the cosine-weighted hemisphere per steradian: cos(theta) / pi.
inline float cosineHemispherePdf(float cosTheta) {
  return std::max(0.0f, cosTheta) * static_cast<float>(M_1_PI);
}

}  // namespace sss
