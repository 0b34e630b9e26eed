// Low-discrepancy points and direction sampling shared by the bake's visibility rays, the light
// tracer and the Monte Carlo walks; each sampler stands beside its pdf (after pbrt-v4's
// util/sampling.h). A direction sampler about an axis returns a unit vector; its pdf is per
// steradian and depends only on the cosine to the axis.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "core/random.h"

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

// The unit direction at polar cosine cosTheta and azimuth phi about unit `axis`, in the basis of
// orthonormalBasis (pbrt-v4's SphericalDirection in Frame::FromZ). Computed in double, each
// component rounded to float before the sum.
inline glm::vec3 directionAbout(const glm::vec3& axis, double cosTheta, double phi) {
  const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
  glm::vec3 b1, b2;
  orthonormalBasis(axis, b1, b2);
  return glm::normalize(static_cast<float>(sinTheta * std::cos(phi)) * b1 +
                        static_cast<float>(sinTheta * std::sin(phi)) * b2 +
                        static_cast<float>(cosTheta) * axis);
}

// Cosine-weighted hemisphere: two mappings of the unit square with the same density,
// cosineHemispherePdf. The concentric one keeps the stratification of its points (for the
// low-discrepancy visibility rays); the polar one is the cheaper mapping of independent random
// numbers (for the walks). They give different directions for the same (u1, u2).

// Concentric: Shirley & Chiu 1997's disk mapping lifted to the hemisphere about +Z (Malley's
// method).
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

// Polar: the disk point at radius sqrt(u1), azimuth 2 pi u2, lifted (Malley's method) into the
// hemisphere about unit n.
inline glm::vec3 sampleCosineHemispherePolar(const glm::vec3& n, double u1, double u2) {
  const float r = static_cast<float>(std::sqrt(u1));
  const float phi = static_cast<float>(2.0 * M_PI * u2);
  glm::vec3 b1, b2;
  orthonormalBasis(n, b1, b2);
  return glm::normalize(r * std::cos(phi) * b1 + r * std::sin(phi) * b2 +
                        static_cast<float>(std::sqrt(std::max(0.0, 1.0 - u1))) * n);
}
// The same with u1 then u2 drawn from rng.
inline glm::vec3 sampleCosineHemispherePolar(const glm::vec3& n, Pcg32& rng) {
  const double u1 = rng.uniformDouble(), u2 = rng.uniformDouble();
  return sampleCosineHemispherePolar(n, u1, u2);
}

// Density of the cosine-weighted hemisphere per steradian: cos(theta) / pi.
inline float cosineHemispherePdf(float cosTheta) {
  return std::max(0.0f, cosTheta) * static_cast<float>(M_1_PI);
}

// Uniform in the solid angle of the cone of directions within acos(cosThetaMax) of unit `axis`
// (cosThetaMax in [-1, 1)): the cosine uniform in [cosThetaMax, 1], the azimuth 2 pi u2.
inline glm::vec3 sampleUniformCone(const glm::vec3& axis, double cosThetaMax, double u1,
                                   double u2) {
  const double cosTheta = 1.0 - u1 * (1.0 - cosThetaMax);
  return directionAbout(axis, cosTheta, 2.0 * M_PI * u2);
}

// Density of sampleUniformCone per steradian inside the cone: 1 / (2 pi (1 - cosThetaMax)).
inline double uniformConePdf(double cosThetaMax) {
  return 1.0 / (2.0 * M_PI * (1.0 - cosThetaMax));
}

// The Henyey-Greenstein phase function's cosine between the old and new direction, from u in
// [0, 1) by inverting its distribution (g > 0 scatters forward); uniform for |g| < 1e-4, where the
// inversion loses precision.
inline double sampleHenyeyGreensteinCosine(double g, double u) {
  if (std::abs(g) < 1e-4) return 1.0 - 2.0 * u;
  const double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
  return std::clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
}

// New propagation direction after scattering from direction d: the cosine from u1, the azimuth
// 2 pi u2. Symmetric in the two directions, so an adjoint walk samples it the same way.
inline glm::vec3 sampleHenyeyGreenstein(const glm::vec3& d, double g, double u1, double u2) {
  return directionAbout(d, sampleHenyeyGreensteinCosine(g, u1), 2.0 * M_PI * u2);
}
// The same with u1 then u2 drawn from rng.
inline glm::vec3 sampleHenyeyGreenstein(const glm::vec3& d, double g, Pcg32& rng) {
  const double u1 = rng.uniformDouble(), u2 = rng.uniformDouble();
  return sampleHenyeyGreenstein(d, g, u1, u2);
}

// The Henyey-Greenstein phase function per steradian at cosine cosTheta between the two
// directions: (1 - g^2) / (4 pi (1 + g^2 - 2 g cosTheta)^(3/2)) (Henyey & Greenstein 1941).
inline double henyeyGreensteinPdf(double g, double cosTheta) {
  const double denom = 1.0 + g * g - 2.0 * g * cosTheta;
  return (1.0 - g * g) / (4.0 * M_PI * denom * std::sqrt(denom));
}

}  // namespace sss
