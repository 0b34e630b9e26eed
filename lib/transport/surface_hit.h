// Where a ray meets the mesh, as the light the object sends itself needs it: the gather's rays
// (interreflection.cpp) and the compact lights' mirror images (mirrored_lights.cpp) reflect at
// the same smooth normal, so that both describe one specular surface.
#pragma once

#include <span>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "core/barycentric.h"
#include "raytrace/triangle_scene.h"

namespace sss {

// Where a ray meets the mesh, as the gather needs it: the hit triangle's vertices and barycentric
// weights, the smooth normal there and the cosine between it and the way back along the ray.
struct SurfaceHit {
  bool hit = false;    // met the mesh
  bool valid = false;  // met the front of a surface
  glm::uvec3 vertices{0};
  glm::vec3 barycentric{0.0f}, point{0.0f}, normal{0.0f}, faceNormal{0.0f};
  float mu = 0.0f;  // cosine between the normal and -direction
};

inline SurfaceHit surfaceHitOf(const SceneHit& hit, std::span<const glm::vec3> positions,
                               std::span<const glm::vec3> normals,
                               std::span<const glm::uvec3> triangles, const glm::vec3& origin,
                               const glm::vec3& direction) {
  SurfaceHit s;
  if (!hit.hit) return s;
  s.hit = true;
  s.vertices = triangles[hit.triangle];
  s.point = origin + hit.t * direction;
  s.barycentric = glm::vec3(barycentricWeights(s.point, positions[s.vertices.x],
                                               positions[s.vertices.y], positions[s.vertices.z]));
  s.normal = glm::normalize(s.barycentric.x * normals[s.vertices.x] +
                            s.barycentric.y * normals[s.vertices.y] +
                            s.barycentric.z * normals[s.vertices.z]);
  s.faceNormal = hit.faceNormal;
  // The cosine by the smooth normal, as B's exit model is; where a facet seen from its front has
  // a smooth normal turned away (the rim of a concavity), by the facet's.
  s.mu = -glm::dot(direction, s.normal);
  if (!(s.mu > 0.0f)) s.mu = -glm::dot(direction, hit.faceNormal);
  s.valid = s.mu > 0.0f;  // else the back of a surface: no light leaves towards the origin
  return s;
}

// The mirror direction at a hit of a ray going `incoming`.
inline glm::vec3 mirrorDirection(const SurfaceHit& h, const glm::vec3& incoming) {
  return incoming + 2.0f * h.mu * h.normal;
}

}  // namespace sss
