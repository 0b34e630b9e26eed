// Generated test meshes with exact, consistent outward (counter-clockwise) winding and unit
// normals, for everyone's tests and benchmarks. Sizes are in mesh units.
#pragma once

#include <glm/vec3.hpp>

#include "mesh/triangle_mesh.h"

namespace sss {

// Subdivided icosahedron on a sphere of `radius` around the origin: 10*4^s + 2 vertices,
// 20*4^s triangles. Normals are the exact sphere normals.
TriangleMesh makeIcosphere(int subdivisions, float radius);

// Square plane in z = 0 centred at the origin, side `size`, n x n quads (n+1)^2 vertices,
// 2 n^2 triangles, normals +Z. Open (has a boundary).
TriangleMesh makeGridPlane(int n, float size);

// Closed axis-aligned box centred at the origin with edge lengths `size`, each face an
// s x s grid (shared edge vertices are welded). Normals: area-weighted (corners and edges are
// the averages of the adjacent faces).
TriangleMesh makeBox(const glm::vec3& size, int subdivisions);

// Closed slab: a box of side `width` x `width` and `thickness` in z, centred at the origin, with
// n x n quads on the large faces and about `thickness / (width / n)` rows on the sides.
TriangleMesh makeSlab(float width, float thickness, int n);

}  // namespace sss
