#include "bake/prepare_mesh.h"

#include "core/bounds.h"
#include "core/error.h"
#include "core/format.h"
#include "core/timer.h"
#include "core/tool.h"

namespace sss {

PreparedMesh prepareMesh(const MeshPreparation& in) {
  const Stopwatch clock;
  PreparedMesh out;
  MeshStageReport& report = out.report;
  report.file = in.path;
  out.mesh = loadMesh(in.path, &report.load);
  for (const std::string& w : report.load.warnings) warn(in.path + ": " + w);

  const double longest = boundsOf(out.mesh.positions).longestSide();
  report.mmPerUnit = in.mmPerUnit;
  if (in.sizeMm > 0.0) {
    if (!(longest > 0.0)) fail(in.path, "the mesh has no extent to scale to a size");
    report.mmPerUnit = in.sizeMm / longest;
  }
  report.longestSideMm = longest * report.mmPerUnit;
  if (report.longestSideMm < 0.01 || report.longestSideMm > 1e6) {
    warn(in.path + ": the mesh is " + format("%g", report.longestSideMm) +
         " mm long: check its units");
  }
  out.meshMm = out.mesh;
  scalePositions(out.meshMm, report.mmPerUnit);
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
