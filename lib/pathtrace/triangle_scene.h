// An Embree 3 BVH over a triangle mesh for the Monte Carlo walks and the interior-segment guard:
// nearest hit with its outward face normal, and occlusion. Embree stays out of this header.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <glm/vec3.hpp>

namespace sss {

struct SceneHit {
  float t = 0.0f;              // distance along the (unit) direction; only valid when hit
  glm::vec3 faceNormal{0.0f};  // unit, by the triangle's winding (outward for a CCW-out mesh)
  uint32_t triangle = 0;       // index of the triangle hit
  bool hit = false;
};

class TriangleScene {
 public:
  // Throws Error if Embree cannot build the scene.
  TriangleScene(const std::vector<glm::vec3>& positions, const std::vector<glm::uvec3>& triangles);
  ~TriangleScene();
  TriangleScene(const TriangleScene&) = delete;
  TriangleScene& operator=(const TriangleScene&) = delete;

  // Thread-safe queries; direction must be unit length.
  SceneHit intersect(const glm::vec3& origin, const glm::vec3& direction, float tNear = 0.0f,
                     float tFar = 1e30f) const;
  bool occluded(const glm::vec3& origin, const glm::vec3& direction, float tNear = 0.0f,
                float tFar = 1e30f) const;

  // A length for ray offsets: 4e-6 of the larger of the bounding box diagonal and the largest
  // coordinate magnitude (~70 float spacings there).
  float epsilon() const { return epsilon_; }
  float diagonal() const { return diagonal_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<glm::vec3> faceNormals_;
  float epsilon_ = 0.0f;
  float diagonal_ = 0.0f;
};

}  // namespace sss
