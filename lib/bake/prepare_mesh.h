// Bake stage 1: the mesh, loaded and cleaned (lib/mesh/load_mesh.h), and scaled to millimetres,
// the unit of the material's coefficients.
#pragma once

#include <string>
#include <vector>

#include "mesh/load_mesh.h"
#include "mesh/triangle_mesh.h"

namespace sss {

struct MeshPreparation {
  std::string path;
  double mmPerUnit = 0.0;  // used when sizeMm is 0
  double sizeMm = 0.0;     // > 0: the longest bounding-box side becomes this long
  bool quiet = false;
};

struct MeshStageReport {
  std::string file;
  MeshReport load;  // counts and cleanup of lib/mesh
  std::size_t vertices = 0, triangles = 0;
  double surfaceAreaMm2 = 0.0;
  double mmPerUnit = 0.0;
  double longestSideMm = 0.0;
  double seconds = 0.0;
};

struct PreparedMesh {
  TriangleMesh mesh;            // in the file's units
  TriangleMesh meshMm;          // the same in mm
  std::vector<float> areasMm2;  // per vertex: a third of its triangles' areas (Li & Guo's M)
  MeshStageReport report;
};

// Warns (warn()) about the mesh's cleanup and about an implausible size. Throws Error naming the
// file.
PreparedMesh prepareMesh(const MeshPreparation& in);

}  // namespace sss
