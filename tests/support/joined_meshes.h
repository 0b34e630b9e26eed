// Two bodies in one mesh, for the tests that need an object beside (or in the shadow of) another.
#pragma once

#include <cstdint>

#include <glm/vec3.hpp>

#include "mesh/triangle_mesh.h"

namespace sss {

// `first` with `second` appended, its positions moved by `shift` (mm), its normals as they are.
inline TriangleMesh joinedMeshes(TriangleMesh first, const TriangleMesh& second,
                                 const glm::vec3& shift) {
  const uint32_t offset = uint32_t(first.positions.size());
  for (const glm::vec3& p : second.positions) first.positions.push_back(p + shift);
  first.normals.insert(first.normals.end(), second.normals.begin(), second.normals.end());
  for (const glm::uvec3& t : second.triangles) first.triangles.push_back(t + glm::uvec3(offset));
  return first;
}

}  // namespace sss
