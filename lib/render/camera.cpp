#include "render/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/trigonometric.hpp>

#include "core/bounds.h"

namespace sss {

glm::mat4 Camera::view() const {
  return glm::lookAt(eye, target, up);
}

glm::mat4 Camera::projection(float aspect) const {
  return glm::perspective(glm::radians(fovYDeg), aspect, nearPlane, farPlane);
}

BoundingSphere boundingSphere(const std::vector<glm::vec3>& points) {
  BoundingSphere s;
  if (points.empty()) return s;
  s.centre = boundsOf(points).center();
  float r2 = 0.0f;
  for (const glm::vec3& p : points) r2 = std::max(r2, glm::dot(p - s.centre, p - s.centre));
  s.radius = std::max(std::sqrt(r2), 1e-6f);
  return s;
}

void fitClipPlanes(Camera& camera, const BoundingSphere& bounds) {
  const float d = glm::length(camera.eye - bounds.centre);
  camera.farPlane = d + 1.01f * bounds.radius;
  // A near plane far from zero keeps depth precision; inside the sphere, a small fraction.
  camera.nearPlane = std::max(d - 1.01f * bounds.radius, 1e-3f * camera.farPlane);
}

Camera orbitCamera(const BoundingSphere& bounds, float azimuthDeg, float elevationDeg,
                   float distance, float fovYDeg, float aspect) {
  Camera camera;
  camera.fovYDeg = fovYDeg;
  if (distance <= 0.0f) {
    // The sphere fits when its angular radius is the smaller half field of view.
    const float halfY = glm::radians(fovYDeg) * 0.5f;
    const float halfX = std::atan(std::tan(halfY) * aspect);
    distance = 1.05f * bounds.radius / std::sin(std::min(halfX, halfY));
  }
  const float az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
  const glm::vec3 dir(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
  camera.eye = bounds.centre + distance * dir;
  camera.target = bounds.centre;
  // Looking straight up or down, Y cannot be the up vector: take the horizontal forward one.
  camera.up = std::abs(std::sin(el)) > 0.999f ? glm::vec3(-std::sin(az), 0.0f, -std::cos(az))
                                              : glm::vec3(0.0f, 1.0f, 0.0f);
  fitClipPlanes(camera, bounds);
  return camera;
}

}  // namespace sss
