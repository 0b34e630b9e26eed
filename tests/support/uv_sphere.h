// A UV sphere as a GLB with TEXCOORD_0 (u the azimuth / 2 pi, v the polar angle / pi from +z), as
// modelling tools export one: the seam's vertices repeated at u = 0 and 1 and a row of vertices at
// each pole (the reader welds them). For the texture bake's test and study.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <glm/gtc/constants.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "support/gltf_builder.h"

namespace sss::test {

// The unit direction at texture coordinates (u, v).
inline glm::vec3 sphereDirection(float u, float v) {
  const float phi = 2.0f * glm::pi<float>() * u, theta = glm::pi<float>() * v;
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// `segments` x `rings` quads (triangles at the poles), radius in metres, as a primitive of b;
// only the rings [firstRing, endRing) (endRing -1: to the last), for a sphere made of parts.
inline GltfBuilder::Primitive uvSpherePrimitive(GltfBuilder& b, int segments, int rings,
                                                float radius, int firstRing = 0, int endRing = -1) {
  std::vector<glm::vec3> positions, normals;
  std::vector<glm::vec2> uv;
  for (int r = 0; r <= rings; ++r) {
    for (int s = 0; s <= segments; ++s) {
      const glm::vec2 t(float(s) / segments, float(r) / rings);
      const glm::vec3 d = sphereDirection(t.x, t.y);
      positions.push_back(radius * d);
      normals.push_back(d);
      uv.push_back(t);
    }
  }
  std::vector<unsigned> idx;
  const auto at = [&](int r, int s) { return unsigned(r * (segments + 1) + s); };
  for (int r = firstRing; r < (endRing < 0 ? rings : endRing); ++r) {
    for (int s = 0; s < segments; ++s) {
      // Outward winding: u turns anticlockwise about +z, v runs from +z down.
      if (r > 0) idx.insert(idx.end(), {at(r, s), at(r + 1, s), at(r, s + 1)});
      if (r < rings - 1) idx.insert(idx.end(), {at(r, s + 1), at(r + 1, s), at(r + 1, s + 1)});
    }
  }
  GltfBuilder::Primitive p;
  p.attributes = {
      {"POSITION", b.positions(positions)},
      {"NORMAL", b.accessor(b.view(GltfBuilder::bytesOf(normals)), 5126, normals.size(), "VEC3")},
      {"TEXCOORD_0", b.texcoords(uv)}};
  p.indices = b.indices(idx);
  return p;
}

// The sphere as a GLB: one node "sphere" placing the mesh "sphere".
inline std::string uvSphereGlb(int segments, int rings, float radius) {
  GltfBuilder b;
  const GltfBuilder::Primitive p = uvSpherePrimitive(b, segments, rings, radius);
  b.scene({b.node({{"name", "sphere"}, {"mesh", b.mesh({p}, "sphere")}})});
  return b.glb();
}

}  // namespace sss::test
