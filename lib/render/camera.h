// A pinhole camera: where it is, what it looks at, and how wide it sees. World Y is up, as in
// the environment convention; azimuth 0 looks from +Z towards -Z, so the equirect image centre
// (which looks to -Z) is behind the model.
#pragma once

#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace sss {

struct Camera {
  glm::vec3 eye = glm::vec3(0.0f, 0.0f, 3.0f);
  glm::vec3 target = glm::vec3(0.0f);
  glm::vec3 up = glm::vec3(0.0f, 1.0f, 0.0f);
  float fovYDeg = 35.0f;  // vertical field of view
  float nearPlane = 0.01f, farPlane = 100.0f;

  glm::mat4 view() const;
  glm::mat4 projection(float aspect) const;
};

// A sphere that encloses the model: centre and radius.
struct BoundingSphere {
  glm::vec3 centre = glm::vec3(0.0f);
  float radius = 1.0f;
};
// Centred on the bounding box, radius to the farthest point.
BoundingSphere boundingSphere(const std::vector<glm::vec3>& points);

// Orbit placement: the camera looks at the sphere's centre from `azimuthDeg` (about +Y,
// 0 = from +Z, 90 = from +X) and `elevationDeg` (above the horizon). distance <= 0 picks the
// distance at which the sphere fills the view with a small margin, for this aspect ratio.
// Near and far planes enclose the sphere.
Camera orbitCamera(const BoundingSphere& bounds, float azimuthDeg, float elevationDeg,
                   float distance, float fovYDeg, float aspect);

// Near and far planes that enclose the sphere seen from `camera.eye`.
void fitClipPlanes(Camera& camera, const BoundingSphere& bounds);

}  // namespace sss
