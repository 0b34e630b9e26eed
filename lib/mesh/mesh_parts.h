// What a scene file (glTF) holds beyond one triangle mesh, kept through loadMesh's cleanup: the
// unit the format fixes, its parts (one per mesh primitive that a node places) with their names
// and materials, each triangle's part, the texture coordinates at each triangle's corners, and
// the surface materials (surface_material.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>

#include "mesh/surface_material.h"

namespace sss {

struct MeshPart {
  std::string node;  // the node's name ("" when unnamed)
  std::uint64_t nodeIndex = 0;
  std::string mesh;  // the mesh's name ("" when unnamed)
  std::uint64_t meshIndex = 0;
  std::uint64_t primitive = 0;  // its index among the mesh's primitives
  // The material's key for a material map: its name, "#<index>" when unnamed, "" for none.
  std::string material;
  std::int64_t materialIndex = -1;  // into MeshParts::surfaces.materials; -1: none
  glm::dmat4 transform{1.0};        // the node's world transform (file units)
  bool hasTexcoords = false;        // TEXCOORD_0 present (else its corners hold 0, 0)
  std::size_t triangles = 0;        // as read, before the cleanup
};

struct MeshParts {
  double mmPerUnit = 0.0;       // the unit the format fixes (glTF: metres, 1000); 0: not given
  std::vector<MeshPart> parts;  // empty for formats without parts
  std::vector<std::uint32_t> trianglePart;  // per triangle of the cleaned mesh (with parts)
  std::vector<glm::vec2> cornerTexcoords;   // 3 per triangle, TEXCOORD_0 (empty: none)
  std::size_t weldedVertices = 0;           // vertices merged at identical positions
  SurfaceMaterials surfaces;                // the file's materials, for an asset written back

  // The distinct material keys of the parts, in the order of first use.
  std::vector<std::string> materials() const {
    std::vector<std::string> keys;
    for (const MeshPart& p : parts) {
      bool seen = false;
      for (const std::string& k : keys) seen = seen || k == p.material;
      if (!seen) keys.push_back(p.material);
    }
    return keys;
  }
};

}  // namespace sss
