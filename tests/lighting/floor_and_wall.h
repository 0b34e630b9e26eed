// The partly shadowed test scene of the visibility tests.
#pragma once

#include <glm/vec3.hpp>

#include "mesh/primitives.h"
#include "mesh/triangle_mesh.h"

namespace sss {

// Floor z = 0 (x, y in [-5, 5], normal +Z) and a wall x = -5 (y in [-5, 5], z in [0, 10],
// normal +X), as separate sheets: half the floor is in partial shadow.
inline TriangleMesh floorAndWall(int n) {
  TriangleMesh floor = makeGridPlane(n, 10.0f);
  TriangleMesh mesh = floor;
  const unsigned offset = static_cast<unsigned>(mesh.positions.size());
  for (const glm::vec3& p : floor.positions) {
    mesh.positions.push_back(glm::vec3(-5.0f, p.x, p.y + 5.0f));
    mesh.normals.push_back(glm::vec3(1.0f, 0.0f, 0.0f));
  }
  for (const glm::uvec3& t : floor.triangles) mesh.triangles.push_back(t + glm::uvec3(offset));
  return mesh;
}

}  // namespace sss
