#include "bake/texture_stage.h"

#include <string>

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "core/bounds.h"
#include "core/error.h"
#include "core/srgb.h"
#include "core/timer.h"
#include "core/tool.h"
#include "image/image.h"
#include "optics/fresnel.h"

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
  out.source = {mesh.mesh, mesh.parts};
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

namespace {

// A typical thickness of the object, mm: the mean chord 4 V / A of a closed body (Cauchy), else
// its bounding box's smallest side.
double typicalThicknessMm(const TriangleMesh& mesh, double mmPerUnit) {
  const glm::vec3 side = boundsOf(mesh.positions).extent();
  const double smallest = std::min({side.x, side.y, side.z});
  const double area = surfaceArea(mesh);
  const double chord = area > 0.0 ? 4.0 * std::abs(signedVolume(mesh)) / area : 0.0;
  return (chord > 0.0 && chord <= smallest ? chord : smallest) * mmPerUnit;
}

// The coat's weight c that makes its reflectance c F_Schlick(mu, 1.5) closest to the material's
// F_r(mu, eta) in least squares over a sphere's image (mu weighted by its projected area, 2 mu
// dmu), so that the reflection and the emission's darkening follow the material's Fresnel factor
// and not the coat's fixed index: 0.82 for eta 1.3, 0.92 for 1.4, 0.99 for 1.5. Measured in the
// browser check: 39 -> 41 dB on marble, 33 -> 35 dB on skin1 under forest.exr.
double coatWeightFor(double eta) {
  constexpr int kSteps = 1000;
  double matched = 0.0, coat = 0.0;
  for (int k = 0; k < kSteps; ++k) {
    const float mu = (k + 0.5f) / kSteps;
    const double schlick = fresnelSchlick(mu, static_cast<float>(kCoatIor));
    matched += schlick * fresnelDielectric(mu, static_cast<float>(eta)) * mu;
    coat += schlick * schlick * mu;
  }
  return std::clamp(matched / coat, 0.0, 1.0);
}

// asset.extras.sss of a lightmapped GLB (mesh/lightmapped_glb.h).
std::string lightmapExtras(const LightmappedAsset& a, int size, const std::string& reportJson) {
  using Json = nlohmann::ordered_json;
  const glm::dvec3 &sa = a.medium.sigmaAPerMm, &ss = a.medium.sigmaSPrimePerMm;
  Json sss = {{"format", 1}, {"position_unit", "m"}, {"mm_per_unit", a.mmPerUnit}};
  sss["material"] = {{"name", a.medium.name},
                     {"sigma_a_per_mm", {sa.x, sa.y, sa.z}},
                     {"sigma_s_prime_per_mm", {ss.x, ss.y, ss.z}},
                     {"eta", a.eta}};
  sss["emission"] = {{"quantity", "radiance along the normal / coat transmittance at normal"},
                     {"units", "the environment's radiance"},
                     {"texture_size", size},
                     {"emissive_strength", a.emissiveStrength},
                     {"coat_ior", kCoatIor},
                     {"coat_weight", a.coatWeight}};
  if (!reportJson.empty()) sss["report"] = Json::parse(reportJson);
  return sss.dump();
}

}  // namespace

LightmappedAsset lightmappedAsset(const TextureSource& source, const Lightmap& map,
                                  const BakedMesh& baked,
                                  const std::vector<Material>& partMaterials,
                                  const std::string& reportJson) {
  const std::vector<glm::vec3>& radiance = map.images[0];
  const double coatWeight = coatWeightFor(baked.eta);
  const double coatTransmittance = 1.0 - coatWeight * kCoatNormalReflectance;
  float peak = 0.0f;
  for (const glm::vec3& l : radiance) peak = std::max({peak, l.x, l.y, l.z});
  const double strength = (peak > 0.0f ? peak : 1.0f) / coatTransmittance;
  std::vector<std::uint8_t> srgb(radiance.size() * 3);
  for (std::size_t i = 0; i < radiance.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const double emission = radiance[i][c] / coatTransmittance;
      srgb[3 * i + c] = linearToSrgbByte(static_cast<float>(emission / strength));
    }
  }
  LightmappedAsset asset;
  asset.coatWeight = coatWeight;
  asset.mesh = source.mesh;
  asset.mmPerUnit = baked.mmPerUnit;
  asset.parts = source.parts;
  asset.emissivePng =
      encodePng("the lightmap",
                {.width = map.size, .height = map.size, .srgb8 = srgb.data(), .attributes = {}});
  asset.emissiveStrength = strength;
  asset.medium = {baked.materialName, baked.sigmaA, baked.sigmaSPrime};
  asset.eta = baked.eta;
  for (const Material& m : partMaterials)
    asset.partMedia.push_back({m.name, m.sigmaA, m.sigmaSPrime});
  asset.thicknessM = typicalThicknessMm(source.mesh, baked.mmPerUnit) / 1000.0;
  asset.extrasJson = lightmapExtras(asset, map.size, reportJson);
  return asset;
}

}  // namespace sss
