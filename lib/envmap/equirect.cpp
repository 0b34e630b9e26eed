#include "envmap/equirect.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace sss {

glm::vec3 equirectDirection(float u, float v) {
  const float phi = 2.0f * static_cast<float>(M_PI) * (u - 0.5f);
  const float theta = static_cast<float>(M_PI) * v;
  const float st = std::sin(theta);
  return {st * std::sin(phi), std::cos(theta), -st * std::cos(phi)};
}

glm::vec2 equirectCoord(const glm::vec3& direction) {
  const glm::vec3 d = glm::normalize(direction);
  const float theta = std::acos(std::clamp(d.y, -1.0f, 1.0f));
  const float phi = std::atan2(d.x, -d.z);
  float u = phi / (2.0f * static_cast<float>(M_PI)) + 0.5f;
  if (u >= 1.0f) u -= 1.0f;
  return {u, theta / static_cast<float>(M_PI)};
}

}  // namespace sss
