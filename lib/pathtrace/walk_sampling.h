// Direction sampling shared by the random walks of lib/pathtrace: the Henyey-Greenstein phase
// function, refraction through and reflection at a smooth boundary and the cosine-weighted outside
// direction whose refraction starts a walk (the basis around a direction: core/sampling.h).
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "core/random.h"
#include "core/sampling.h"

namespace sss {

// New propagation direction after scattering: Henyey-Greenstein in the cosine to the old one
// (symmetric, so an adjoint walk samples it the same way); uniform for g = 0.
inline glm::vec3 sampleHenyeyGreenstein(const glm::vec3& d, double g, Pcg32& rng) {
  const double u1 = rng.uniformDouble(), u2 = rng.uniformDouble();
  double cosTheta;
  if (std::abs(g) < 1e-4) {
    cosTheta = 1.0 - 2.0 * u1;
  } else {
    const double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u1);
    cosTheta = std::clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
  }
  const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
  const double phi = 2.0 * M_PI * u2;
  glm::vec3 b1, b2;
  orthonormalBasis(d, b1, b2);
  return glm::normalize(static_cast<float>(sinTheta * std::cos(phi)) * b1 +
                        static_cast<float>(sinTheta * std::sin(phi)) * b2 +
                        static_cast<float>(cosTheta) * d);
}

// Refraction of unit d through a boundary whose unit normal n points to the transmitted side
// (dot(d, n) > 0); ratio = n_incident / n_transmitted. Caller excludes total internal reflection.
inline glm::vec3 refractDirection(const glm::vec3& d, const glm::vec3& n, float ratio) {
  const float cosI = glm::dot(d, n);
  const float cosT = std::sqrt(std::max(0.0f, 1.0f - ratio * ratio * (1.0f - cosI * cosI)));
  return glm::normalize(ratio * d + (cosT - ratio * cosI) * n);
}

// Where a walk inside meets the boundary: the face normal turned to point out along the walk's
// direction d (a back face of an open or inconsistent mesh is crossed anyway) and the cosine of
// incidence, >= 0.
struct BoundaryCrossing {
  glm::vec3 normal;
  float cosI;
};
inline BoundaryCrossing boundaryCrossing(const glm::vec3& d, const glm::vec3& faceNormal) {
  const float cosI = glm::dot(d, faceNormal);
  return cosI < 0.0f ? BoundaryCrossing{-faceNormal, -cosI} : BoundaryCrossing{faceNormal, cosI};
}

// Mirror reflection of d back inside at that crossing.
inline glm::vec3 reflectInside(const glm::vec3& d, const BoundaryCrossing& b) {
  return glm::normalize(d - 2.0f * b.cosI * b.normal);
}

// Cosine-weighted direction in the hemisphere around unit n.
inline glm::vec3 sampleCosineHemisphere(const glm::vec3& n, Pcg32& rng) {
  const double u1 = rng.uniformDouble(), u2 = rng.uniformDouble();
  const float r = static_cast<float>(std::sqrt(u1));
  const float phi = static_cast<float>(2.0 * M_PI * u2);
  glm::vec3 b1, b2;
  orthonormalBasis(n, b1, b2);
  return glm::normalize(r * std::cos(phi) * b1 + r * std::sin(phi) * b2 +
                        static_cast<float>(std::sqrt(std::max(0.0, 1.0 - u1))) * n);
}

}  // namespace sss
