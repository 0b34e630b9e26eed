#include "bake/texture_stage.h"

#include <string>

#include "core/error.h"
#include "core/timer.h"
#include "core/tool.h"

namespace sss {
namespace {

// Refinement stops here whatever the memory: a 4096^2 map fully covered needs about 17M.
constexpr std::size_t kMaxRefinedVertices = std::size_t(1) << 25;

}  // namespace

TextureMesh refineForTexture(PreparedMesh mesh, const TextureSettings& s, bool quiet) {
  const Stopwatch clock;
  const std::string& path = mesh.report.file;
  if (mesh.parts.cornerTexcoords.empty()) {
    fail(path, "--texture needs texture coordinates (a glTF with TEXCOORD_0); this mesh has none");
  }
  TextureMesh out;
  out.file = path;
  out.refinement =
      refineToTexels(path, mesh.mesh.vertexCount(), mesh.mesh.triangles, mesh.parts.cornerTexcoords,
                     s.size, s.edgeTexels, kMaxRefinedVertices);
  const UvRefinement& r = out.refinement;
  checkBakeMemory(path, r.vertexCount(), r.triangles.size());
  LightmapReport& report = out.report;
  report.size = s.size;
  report.padding = s.padding;
  report.originalVertices = mesh.mesh.vertexCount();
  report.originalTriangles = mesh.mesh.triangleCount();
  mesh.mesh = refinedMesh(r, mesh.mesh);
  mesh.meshMm = refinedMesh(r, mesh.meshMm);
  mesh.areasMm2 = vertexAreas(mesh.meshMm);
  mesh.parts.cornerTexcoords = r.cornerTexcoords;
  if (!mesh.parts.trianglePart.empty()) {
    std::vector<std::uint32_t> parts(r.triangles.size());
    for (std::size_t t = 0; t < parts.size(); ++t) {
      parts[t] = mesh.parts.trianglePart[r.parentTriangle[t]];
    }
    mesh.parts.trianglePart = std::move(parts);
  }
  report.refinedVertices = r.vertexCount();
  report.refinedTriangles = r.triangles.size();
  report.refineSeconds = clock.seconds();
  info("texture: " + std::to_string(s.size) + "^2 texels; the mesh refined to " +
           std::to_string(report.refinedVertices) + " vertices, " +
           std::to_string(report.refinedTriangles) + " triangles",
       quiet);
  out.mesh = std::move(mesh);
  return out;
}

BakedLightmap bakeLightmap(const TextureMesh& texture, const BakedMesh& baked,
                           const TextureSettings& s, bool quiet) {
  const Stopwatch clock;
  BakedLightmap out;
  const std::span<const glm::vec3> fields[] = {baked.radianceNormal, baked.exitance};
  out.map = fillLightmap(texture.refinement, fields, {.size = s.size, .padding = s.padding});
  out.report = texture.report;
  out.report.coveredTexels = out.map.coveredTexels;
  out.report.paddedTexels = out.map.paddedTexels;
  out.report.overlappingTexels = out.map.overlappingTexels;
  out.report.seams = compareSeams(texture.refinement, out.map.images[0], s.size, 8);
  out.report.fillSeconds = clock.seconds();
  if (!quiet && out.map.overlappingTexels > out.map.coveredTexels / 100) {
    warn(texture.file + ": " + std::to_string(out.map.overlappingTexels) +
         " texels lie under two places of the surface (overlapping UV charts): a lightmap needs "
         "a unique unwrap; the later triangle's light is kept");
  }
  return out;
}

}  // namespace sss
