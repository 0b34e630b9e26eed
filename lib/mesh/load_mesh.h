// Loading and validating triangle meshes from PLY (ascii, binary little and big endian), OBJ,
// OFF, STL (ascii and binary), OM and glTF 2.0 (.gltf, .glb: gltf_reader.h, a scene's meshes
// placed by its nodes, welded into one mesh).
//
// Mesh readers are lenient where a bake must not be: OpenMesh 9 accepts a truncated ASCII PLY as
// a smaller mesh, can hang or allocate without bound on a lying header, and silently splits
// non-manifold or duplicate faces apart. So PLY files go through our own strict reader (header
// counts checked against the file size before anything is allocated, every token checked), the
// other formats through OpenMesh's readers into a raw face list (no OpenMesh topology), and the
// cleanup below is ours for every format:
//   - NaN/Inf coordinates, out-of-range indices, zero faces: errors;
//   - coordinates too large or too far apart for float ray tracing (kMaxCoordinate,
//     kMaxReachInEdges below, on the vertices the faces use): errors;
//   - polygons are fan-triangulated; degenerate triangles (repeated index or zero area) and
//     duplicate triangles (same three vertices, any order or winding) are dropped and counted;
//   - unreferenced vertices are removed (counted); a mesh whose faces all drop is an error;
//   - non-manifold edges (more than two triangles), misoriented edges (two triangles with
//     inconsistent winding) and non-manifold vertices (several fans meeting at a vertex) are
//     counted and warned about;
//   - missing (or non-finite, or zero) normals are computed, area-weighted;
//   - a closed mesh (no boundary, manifold, consistently wound) with negative signed volume is
//     turned right side out: its triangles are flipped, with a warning; file normals that point
//     against the (final) winding on the whole are negated, with a warning.
// All errors are sss::Error "<file>: <problem>".
#pragma once

#include <cstddef>
#include <initializer_list>
#include <string>
#include <vector>

#include "mesh/mesh_parts.h"
#include "mesh/raw_mesh.h"
#include "mesh/triangle_mesh.h"

namespace sss {

// Loads, validates and cleans a mesh; the format comes from the extension (case-insensitive).
// `report` (optional) receives counts and warnings; warnings are not printed here. `parts`
// (optional) receives what a glTF holds beyond the mesh (its unit, parts, materials, texture
// coordinates), following the cleanup; other formats leave it empty.
TriangleMesh loadMesh(const std::string& path, MeshReport* report = nullptr,
                      MeshParts* parts = nullptr);

// Geometry that float arithmetic cannot carry: positions are floats (a 24-bit significand, so a
// coordinate x is stored to within |x| 2^-24), and the ray tracer (lib/raytrace) offsets its rays
// by 4e-6, about 2^-18, of the mesh's reach (its farthest coordinate or its bounding-box diagonal,
// whichever is larger). cleanMesh checks, for every reader:
//  - kMaxCoordinate: no coordinate beyond 1e18, under the 1.84e18 Embree allows a ray origin
//    (beyond it its ray.valid() assertion aborts) and under sqrt(FLT_MAX) = 1.8e19, so that
//    squared lengths stay finite in float (bounds, camera distances, the renderer's matrices);
//  - kMaxReachInEdges: the reach is at most 2^16 median edge lengths. Float then resolves an edge
//    in 128 steps or more (spacing <= reach 2^-23) and the ray offset stays under about a quarter
//    of an edge; beyond, rays step over whole triangles and random walks stall where one step
//    does not move a point (a 42-vertex sphere with one vertex 1.7e15 away runs for more than
//    120 s). Scale-free: a whole mesh far from its origin, or one stray vertex, fails alike. The
//    sample meshes reach 22 (teapot) to 643 (871K-triangle dragon) median edges; a regular
//    tessellation reaches 2^16 with some 10^10 triangles.
inline constexpr double kMaxCoordinate = 1e18;
inline constexpr double kMaxReachInEdges = 65536.0;
// The bake's bound after scaling to millimetres (lib/bake/prepare_mesh.cpp): floats hold every
// whole millimetre up to 2^24 mm (16.8 km); beyond, they are 2 mm or more apart, longer than the
// mean free path of all but one preset material (0.14 to 6 mm): walk steps stop moving a point.
inline constexpr double kMaxCoordinateMm = 16777216.0;

// Throws Error("<path>: ...") naming the vertex and the limit when a coordinate's magnitude
// exceeds `maxCoordinate` (`unit` names its unit in the message: "mm", or "" for the file's).
void checkCoordinateRange(const std::string& path, const TriangleMesh& mesh, double maxCoordinate,
                          const std::string& unit = "");
// Throws Error("<path>: ...") naming the farthest vertex when the mesh's reach exceeds
// kMaxReachInEdges median edge lengths (the median of a stride sample of at most 2^16
// triangles' edges: O(n) time, 1.5 MB at most).
void checkFloatPrecision(const std::string& path, const TriangleMesh& mesh);

// The validation and cleanup step of loadMesh on in-memory data. `path` only names the source
// in errors. `vertexOrigin` (optional) receives, for each output vertex, its index in
// raw.positions, so that other per-vertex data can follow; `faceOrigin` (optional), for each
// output triangle, the index of the raw face it came from (its corners may have been turned).
TriangleMesh cleanMesh(const std::string& path, RawMesh raw, MeshReport* report,
                       std::vector<unsigned>* vertexOrigin = nullptr,
                       std::vector<unsigned>* faceOrigin = nullptr);

}  // namespace sss
