// The concave closed test scene of the interreflection tests.
#pragma once

#include <cmath>

#include <glm/vec3.hpp>

#include "mesh/primitives.h"
#include "mesh/triangle_mesh.h"

namespace sss {

// A 20 mm box (12 x 12 quads a face) with a smooth pit 6 mm deep and 8 mm in radius in its top
// face: closed and concave; the pit's floor sees about 70 % of the sky.
inline TriangleMesh boxWithPit() {
  TriangleMesh mesh = makeBox(glm::vec3(20.0f), 12);
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    glm::vec3& p = mesh.positions[v];
    const float r = std::hypot(p.x, p.y);
    if (mesh.normals[v].z > 0.99f && r < 8.0f) p.z -= 6.0f * (1.0f - (r / 8.0f) * (r / 8.0f));
  }
  mesh.normals = computeVertexNormals(mesh);
  return mesh;
}

}  // namespace sss
