// Bake stage 1: the mesh, loaded and cleaned (lib/mesh/load_mesh.h), and scaled to millimetres,
// the unit of the material's coefficients.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mesh/load_mesh.h"
#include "mesh/triangle_mesh.h"

namespace sss {

struct MeshPreparation {
  std::string path;
  double mmPerUnit = 0.0;  // used when sizeMm is 0; 0: the unit the file fixes (glTF: metres)
  double sizeMm = 0.0;     // > 0: the longest bounding-box side becomes this long
  bool quiet = false;      // no progress, and no warnings about the mesh (cleanup, size)
};

struct MeshStageReport {
  std::string file;
  MeshReport load;  // counts and cleanup of lib/mesh
  std::size_t vertices = 0, triangles = 0;
  double surfaceAreaMm2 = 0.0;
  double mmPerUnit = 0.0;
  double longestSideMm = 0.0;
  bool unitFromFile = false;  // mmPerUnit is the file's own unit (glTF: metres)
  // A glTF's parts (mesh/mesh_parts.h: node, mesh, primitive, material, triangles), the vertices
  // welded across them and whether TEXCOORD_0 was read; empty for other formats.
  std::vector<MeshPart> parts;
  std::size_t weldedVertices = 0;
  bool texcoords = false;
  double seconds = 0.0;
};

struct PreparedMesh {
  TriangleMesh mesh;            // in the file's units
  TriangleMesh meshMm;          // the same in mm
  std::vector<float> areasMm2;  // per vertex: a third of its triangles' areas (Li & Guo's M)
  MeshParts parts;              // a glTF's parts, materials and texture coordinates (else empty)
  MeshStageReport report;
};

// Warns (warn(), unless quiet) about the mesh's cleanup and an implausible size. Throws Error
// naming the file, also when the bake would not fit in memory (checkBakeMemory: before loading
// when the header gives the counts).
PreparedMesh prepareMesh(const MeshPreparation& in);

// sss-bake's peak memory for a mesh of `vertices` and `triangles` (vertices 0: unknown), an upper
// estimate from measurements (tests/bench/results/bake/memory.csv).
std::uint64_t estimateBakeBytes(std::uint64_t vertices, std::uint64_t triangles);
// Throws Error("<path>: baking N triangles needs about X GB, Y GB available") when the estimate
// exceeds core/memory.h's availableMemory() (SSS_MEMORY_LIMIT_MB caps it).
void checkBakeMemory(const std::string& path, std::uint64_t vertices, std::uint64_t triangles);

}  // namespace sss
