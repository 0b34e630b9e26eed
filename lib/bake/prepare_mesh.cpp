#include "bake/prepare_mesh.h"

#include <algorithm>

#include "core/bounds.h"
#include "core/error.h"
#include "core/format.h"
#include "core/memory.h"
#include "core/timer.h"
#include "core/tool.h"
#include "mesh/declared_counts.h"

namespace sss {

std::uint64_t estimateBakeBytes(std::uint64_t vertices, std::uint64_t triangles) {
  // Peak RSS of sss-bake, tests/bench/results/bake/memory.csv (memory_sweep.sh): about 135 MB
  // without a mesh (the environment's cubemaps, the libraries), then per triangle 100-135 bytes
  // with --visibility none --energy halfspace and 200-230 bytes by default (Embree's BVH, the
  // escape walks), from 11K to 9.9M triangles. The bound adds a margin to the default's.
  constexpr double kBaseBytes = 150e6, kBytesPerTriangle = 256.0;
  const double elements = std::max(double(triangles), 2.0 * double(vertices));  // closed: T = 2V
  return static_cast<std::uint64_t>(std::min(kBaseBytes + kBytesPerTriangle * elements, 1.8e19));
}

void checkBakeMemory(const std::string& path, std::uint64_t vertices, std::uint64_t triangles) {
  checkMemoryNeed(path, "baking " + std::to_string(triangles) + " triangles",
                  estimateBakeBytes(vertices, triangles));
}

PreparedMesh prepareMesh(const MeshPreparation& in) {
  const Stopwatch clock;
  PreparedMesh out;
  MeshStageReport& report = out.report;
  report.file = in.path;
  // Refused up front when the header gives the counts (PLY, OFF, binary STL), else once loaded.
  const DeclaredMeshCounts declared = declaredMeshCounts(in.path);
  if (declared.known) checkBakeMemory(in.path, declared.vertices, declared.faces);
  out.mesh = loadMesh(in.path, &report.load, &out.parts);
  report.parts = out.parts.parts;
  report.weldedVertices = out.parts.weldedVertices;
  report.texcoords = !out.parts.cornerTexcoords.empty();
  if (!declared.known) checkBakeMemory(in.path, out.mesh.vertexCount(), out.mesh.triangleCount());
  if (!in.quiet) {
    for (const std::string& w : report.load.warnings) warn(in.path + ": " + w);
  }

  const double longest = boundsOf(out.mesh.positions).longestSide();
  report.mmPerUnit = in.mmPerUnit;
  if (in.sizeMm <= 0.0 && in.mmPerUnit <= 0.0) {
    if (!(out.parts.mmPerUnit > 0.0)) {
      fail(in.path,
           "no unit: give --mm-per-unit, --unit or --size-mm (only glTF files fix "
           "theirs, metres)");
    }
    report.mmPerUnit = out.parts.mmPerUnit;
    report.unitFromFile = true;
  }
  if (in.sizeMm > 0.0) {
    if (!(longest > 0.0)) fail(in.path, "the mesh has no extent to scale to a size");
    report.mmPerUnit = in.sizeMm / longest;
  }
  report.longestSideMm = longest * report.mmPerUnit;
  if (!in.quiet && (report.longestSideMm < 0.01 || report.longestSideMm > 1e6)) {
    warn(in.path + ": the mesh is " + format("%g", report.longestSideMm) +
         " mm long: check its units");
  }
  out.meshMm = out.mesh;
  scalePositions(out.meshMm, report.mmPerUnit);
  checkCoordinateRange(in.path, out.meshMm, kMaxCoordinateMm, "mm");
  out.areasMm2 = vertexAreas(out.meshMm);
  report.vertices = out.mesh.vertexCount();
  report.triangles = out.mesh.triangleCount();
  report.surfaceAreaMm2 = surfaceArea(out.meshMm);
  report.seconds = clock.seconds();
  info("mesh: " + std::to_string(report.vertices) + " vertices, " +
           std::to_string(report.triangles) + " triangles, " +
           format("%.4g", report.longestSideMm) + " mm long",
       in.quiet);
  return out;
}

}  // namespace sss
