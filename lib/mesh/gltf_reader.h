// glTF 2.0 scenes (.gltf with external or data: buffers, .glb) as one raw triangle mesh for
// load_mesh.h's cleanup. Following the glTF 2.0 specification:
//   - the scene `scene` names, else scene 0 (section 3.5); its node trees are walked
//     (3.5.2: each node has at most one parent, no cycles), each node's matrix or
//     translation * rotation * scale (3.5.3) accumulated from its parents, in double;
//   - every primitive of every mesh a node places (3.7.2): TRIANGLES (mode 4, the default),
//     TRIANGLE_STRIP (5) and TRIANGLE_FAN (6), as section 3.7.2.1 orders their corners; points and
//     lines are an error naming the primitive;
//   - POSITION (float VEC3), NORMAL (optional, float VEC3; transformed by the inverse transpose and
//     renormalized), TEXCOORD_0 (optional: float, or normalized unsigned byte or short VEC2), and
//     indices of any unsigned component type or none; strided, offset and sparse accessors
//     (gltf_document.h);
//   - a node whose transform mirrors (negative determinant) has its triangles' winding reversed
//     (3.7.2.1), so that they still face outwards;
//   - positions stay in the file's unit, metres (3.3.1); MeshParts.mmPerUnit says so.
// Vertices at bit-identical positions (after the transforms; -0 = +0) are welded across and
// within primitives, as OpenMesh's STL reader welds: so that the parts of an object touch where
// they meet (normals, topology, closed-mesh checks) and a glTF's seams (UVs, hard edges) do not
// split the surface. A welded vertex keeps its one normal when its copies agree, else their
// normalized sum; TEXCOORD_0 stays per triangle corner, so seams keep both sides' coordinates.
// Refused with "<file>: <problem>": what gltf_document.h refuses, extensions that change geometry
// (Draco, meshopt, quantization, GPU instancing) when required, non-finite values and transforms,
// a node graph that is not a forest, absurd totals (checked against the memory before allocating).
// Skins and morph targets are ignored with a warning (the bind pose, the base shape).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "mesh/mesh_parts.h"
#include "mesh/raw_mesh.h"

namespace sss {

struct GltfMesh {
  RawMesh raw;                             // welded; every face a triangle; positions in metres
  std::vector<std::uint32_t> facePart;     // per raw face: its index in parts
  std::vector<glm::vec2> cornerTexcoords;  // 3 per raw face (empty: no part has TEXCOORD_0)
  std::vector<MeshPart> parts;
  SurfaceMaterials surfaces;  // the file's materials (gltf_materials.h)
  std::size_t weldedVertices = 0;
  std::vector<std::string> warnings;  // without the file name
};

// Reads `path`: a .glb container, else glTF JSON. Throws Error "<path>: <problem>".
GltfMesh readGltf(const std::string& path);

}  // namespace sss
