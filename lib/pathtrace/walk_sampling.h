// Direction changes at a smooth boundary shared by the random walks of lib/pathtrace: refraction
// through it and reflection at it (the phase function's and the cosine-weighted samplers, each
// with its pdf: core/sampling.h).
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "core/sampling.h"

namespace sss {

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

}  // namespace sss
