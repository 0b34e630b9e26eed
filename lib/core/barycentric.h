// Barycentric weights of a point on a triangle, shared by the light tracer's exit tallies
// (lib/pathtrace/light_tracer.cpp) and the interreflection gather
// (lib/transport/interreflection.cpp).
#pragma once

#include <algorithm>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace sss {

// Weights (w_a, w_b, w_c) of p, projected onto the plane of triangle abc and clamped onto the
// triangle, summing to 1 (the centroid's for a degenerate triangle). In double: the tallies sum
// many of them.
inline glm::dvec3 barycentricWeights(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b,
                                     const glm::vec3& c) {
  const glm::dvec3 e0(b - a), e1(c - a), ep(p - a);
  const double d00 = glm::dot(e0, e0), d01 = glm::dot(e0, e1), d11 = glm::dot(e1, e1);
  const double d20 = glm::dot(ep, e0), d21 = glm::dot(ep, e1);
  const double den = d00 * d11 - d01 * d01;
  if (!(den > 0.0)) return glm::dvec3(1.0 / 3.0);
  const double v = std::clamp((d11 * d20 - d01 * d21) / den, 0.0, 1.0);
  const double w = std::clamp((d00 * d21 - d01 * d20) / den, 0.0, 1.0 - v);
  return {1.0 - v - w, v, w};
}

}  // namespace sss
