// The texture bake (sss-bake --texture) on a low-poly UV sphere against a dense sphere baked per
// vertex: a 24 x 12 UV sphere (288 welded vertices, 20 mm marble) under a sun at 20 degrees and
// its sky, with sss-bake's defaults, baked per vertex (the light a vertex-colour asset shows,
// interpolated across its facets: fillLightmap over the unrefined mesh) and into maps of 64 to 512
// texels a side (edges of 2 texels, sss-bake's default; and 1 at 256); the reference is a
// 40962-vertex icosphere baked per vertex with the same settings. Each map is read bilinearly at
// 128 x 112 points of the sphere away from the poles (where the UV sphere's facets fold to a point)
// and compared with the reference's nearest vertex (0.6 degrees apart): relative RMS of the
// radiance along the normal. Also the bake's time, the refined vertices, the covered megatexels and
// the seam's agreement.
//   texture_study OUT_DIR   (writes OUT_DIR/sphere.csv)
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "bake/bake.h"
#include "bake/prepare_mesh.h"
#include "core/timer.h"
#include "lightmap/lightmap.h"
#include "mesh/baked_glb.h"
#include "mesh/primitives.h"
#include "support/uv_sphere.h"

namespace sss {
namespace {

constexpr float kRadiusM = 0.01f;

struct Reference {
  std::vector<glm::vec3> directions, radiance;
  // The reference's value in direction d: its nearest vertex's.
  glm::vec3 at(const glm::vec3& d) const {
    std::size_t best = 0;
    for (std::size_t v = 1; v < directions.size(); ++v) {
      if (glm::dot(directions[v], d) > glm::dot(directions[best], d)) best = v;
    }
    return radiance[best];
  }
};

// Relative RMS of a map against the reference at the study's points.
double mapError(const Reference& ref, const std::vector<glm::vec3>& image, int size) {
  double err2 = 0.0, ref2 = 0.0;
  for (int j = 0; j < 112; ++j) {
    for (int i = 0; i < 128; ++i) {
      const glm::vec2 uv((i + 0.5f) / 128.0f, 1.0f / 12.0f + (j + 0.5f) / 112.0f * (10.0f / 12.0f));
      const glm::vec3 want = ref.at(test::sphereDirection(uv.x, uv.y));
      const glm::vec3 got = sampleBilinear(image, size, uv);
      err2 += glm::dot(got - want, got - want);
      ref2 += glm::dot(want, want);
    }
  }
  return std::sqrt(err2 / ref2);
}

BakeSettings settingsFor(const std::string& mesh) {
  BakeSettings s;
  s.meshPath = mesh;
  s.environment = "sky:elevation=20,azimuth=40";
  s.material = findMaterialPreset("marble");
  s.run.quiet = true;
  return s;
}

}  // namespace
}  // namespace sss

int main(int argc, char** argv) {
  using namespace sss;
  if (argc != 2) {
    std::fprintf(stderr, "usage: texture_study OUT_DIR\n");
    return 2;
  }
  const std::filesystem::path work = std::filesystem::temp_directory_path() / "sss-texture-study";
  std::filesystem::create_directories(work);
  std::filesystem::create_directories(argv[1]);
  const std::string sphere = (work / "uv_sphere.glb").string();
  std::ofstream(sphere, std::ios::binary) << test::uvSphereGlb(24, 12, kRadiusM);
  BakedMesh dense;
  dense.mesh = makeIcosphere(6, kRadiusM);
  dense.mmPerUnit = 1000.0;
  const std::string densePath = (work / "dense.glb").string();
  writeBakedGlb(densePath, dense);

  const BakeOutput reference = bake(settingsFor(densePath));
  const Reference ref{reference.baked.mesh.normals, reference.baked.radianceNormal};
  std::ofstream csv(std::string(argv[1]) + "/sphere.csv");
  csv << "mesh,bake,texture_size,edge_texels,baked_vertices,bake_s,covered_megatexels,s_per_"
         "megatexel,"
         "relative_rms_vs_dense,seam_relative_rms,seam_worst\n";
  csv << "icosphere-6,vertex (reference),0,0," << reference.baked.mesh.vertexCount() << ","
      << reference.report.totalSeconds << ",0,0,0,0,0\n";

  // Per vertex, as a vertex-colour asset shows it: interpolated across the 24 x 12 facets.
  const BakeOutput perVertex = bake(settingsFor(sphere));
  const PreparedMesh loaded = prepareMesh({.path = sphere, .quiet = true});  // as the bake did
  const UvRefinement facets =
      refineToTexels(sphere, loaded.mesh.vertexCount(), loaded.mesh.triangles,
                     loaded.parts.cornerTexcoords, 256, 1e9, loaded.mesh.vertexCount());
  const std::span<const glm::vec3> vertexLight[] = {perVertex.baked.radianceNormal};
  const Lightmap gouraud = fillLightmap(facets, vertexLight, {.size = 256, .padding = 4});
  const SeamReport gouraudSeams = compareSeams(facets, gouraud.images[0], 256, 8);
  csv << "uv-sphere-24x12,vertex (interpolated),0,0," << perVertex.baked.mesh.vertexCount() << ","
      << perVertex.report.totalSeconds << ",0,0," << mapError(ref, gouraud.images[0], 256) << ","
      << gouraudSeams.relativeRms << "," << gouraudSeams.worstRelative << "\n";
  // The default edge (2 texels) at every size, and 1 texel at 256 (4x the vertices).
  const std::pair<int, double> runs[] = {{64, 2.0}, {128, 2.0}, {256, 2.0}, {512, 2.0}, {256, 1.0}};
  for (const auto& [size, edge] : runs) {
    BakeSettings s = settingsFor(sphere);
    s.texture.size = size;
    s.texture.edgeTexels = edge;
    const BakeOutput out = bake(s);
    const LightmapReport& r = out.report.lightmap;
    const double megatexels = double(r.coveredTexels) / 1e6;
    const double error = mapError(ref, out.lightmap.images[0], size);
    csv << "uv-sphere-24x12,texture," << size << "," << edge << "," << r.refinedVertices << ","
        << out.report.totalSeconds << "," << megatexels << ","
        << out.report.totalSeconds / megatexels << "," << error << "," << r.seams.relativeRms << ","
        << r.seams.worstRelative << "\n";
    std::printf("%d (edge %g): %zu vertices, %.2f s, error %.4f, seams %.4f\n", size, edge,
                r.refinedVertices, out.report.totalSeconds, error, r.seams.relativeRms);
  }
  std::filesystem::remove_all(work);
  return 0;
}
