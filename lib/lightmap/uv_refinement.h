// A mesh refined so that its vertices sample the surface at least as densely as a UV lightmap's
// texels: the point set a texture bake evaluates (sss-bake --texture, docs/tools/sss-bake.md).
//
// Why: a bake stores its light at the mesh's points. On a low-poly asset those are far apart and
// a texture filled from them shows the triangles (Gouraud bands); refined until every edge spans
// at most about one texel in UV space, the points are as dense as the texels, so the texture's
// detail follows its resolution and not the tessellation.
//
// How: longest-edge bisection (Rivara, "Mesh refinement processes based on the generalized
// bisection of simplices", SIAM J. Numer. Anal. 21(3), 1984), longest edge first over the whole
// mesh. An edge is split at its midpoint in every triangle that shares it, so the mesh stays
// conforming (closed stays closed, no T-junctions) and the new point lies on the original
// surface; each side of a UV seam gets the midpoint of its own texture coordinates. An edge's
// length is its longest extent in texels over the triangles that share it.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "mesh/triangle_mesh.h"

namespace sss {

struct UvRefinement {
  // The refined triangles (the original vertices first, in order, then the new ones) and their
  // texture coordinates, 3 per triangle as the triangles' corners.
  std::vector<glm::uvec3> triangles;
  std::vector<glm::vec2> cornerTexcoords;
  // Per new vertex (index originalVertices + i): the two vertices whose midpoint it is.
  std::vector<std::array<std::uint32_t, 2>> newVertexParents;
  std::vector<std::uint32_t> parentTriangle;       // per refined triangle, the original one
  std::vector<glm::vec2> originalCornerTexcoords;  // 3 per original triangle
  std::size_t originalVertices = 0;
  std::size_t vertexCount() const { return originalVertices + newVertexParents.size(); }
};

// Refines `triangles` (over `vertexCount` vertices, with 3 texture coordinates per triangle in
// [0, 1]) until no edge spans more than maxEdgeTexels texels of a textureSize x textureSize map.
// Throws Error (naming `path`) when the refinement would exceed maxVertices.
UvRefinement refineToTexels(const std::string& path, std::size_t vertexCount,
                            std::span<const glm::uvec3> triangles,
                            std::span<const glm::vec2> cornerTexcoords, int textureSize,
                            double maxEdgeTexels, std::size_t maxVertices);

// A per-vertex value over the refined vertices: the original ones' as given, each new one the
// mean of its parents' (exact for positions: the midpoint of a straight edge).
template <class T>
std::vector<T> refinedValues(const UvRefinement& refinement, std::span<const T> values) {
  std::vector<T> out(values.begin(), values.end());
  out.reserve(refinement.vertexCount());
  for (const auto& [a, b] : refinement.newVertexParents) out.push_back((out[a] + out[b]) * 0.5f);
  return out;
}

// The refined mesh: positions at the edges' midpoints, normals the normalized mean of the edge's
// ends (the interpolated normal a renderer would shade the original triangle with).
TriangleMesh refinedMesh(const UvRefinement& refinement, const TriangleMesh& original);

}  // namespace sss
