// Axis-aligned bounding box of a point set.
#pragma once

#include <algorithm>
#include <limits>
#include <span>

#include <glm/common.hpp>
#include <glm/vec3.hpp>

namespace sss {

struct Bounds3 {
  glm::vec3 lo{std::numeric_limits<float>::infinity()};
  glm::vec3 hi{-std::numeric_limits<float>::infinity()};

  void extend(const glm::vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
  glm::vec3 extent() const { return hi - lo; }
  glm::vec3 center() const { return 0.5f * (lo + hi); }
  float longestSide() const {
    const glm::vec3 e = extent();
    return std::max({e.x, e.y, e.z});
  }
};

inline Bounds3 boundsOf(std::span<const glm::vec3> points) {
  Bounds3 b;
  for (const glm::vec3& p : points) b.extend(p);
  return b;
}

}  // namespace sss
