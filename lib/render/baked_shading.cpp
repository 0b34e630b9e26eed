#include "render/baked_shading.h"

#include <cmath>

#include "material/directional_albedo_weight.h"
#include "material/halfspace_albedo.h"
#include "optics/exit_lobe.h"
#include "optics/fresnel.h"

namespace sss {
namespace {

std::string channels(const char* prefix) {
  return std::string(prefix) + "_r, " + prefix + "_g, " + prefix + "_b";
}

// The material's total diffuse reflectance as the bake models it, per channel: the Monte Carlo
// half-space albedo of its reduced albedo (what a lit plane returns; material/halfspace_albedo.h).
glm::vec3 halfSpaceAlbedo(const BakedMesh& baked, float eta) {
  const glm::dvec3 albedo = baked.sigmaSPrime / (baked.sigmaA + baked.sigmaSPrime);
  glm::vec3 out;
  for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(halfSpaceDiffuseAlbedo(albedo[c], eta));
  return out;
}

}  // namespace

ExitWeightTable exitWeightTable(const BakedMesh& baked, float eta) {
  const glm::dvec3 albedo = baked.sigmaSPrime / (baked.sigmaA + baked.sigmaSPrime);
  const DirectionalAlbedoWeight w(albedo, eta);
  ExitWeightTable table;
  for (int k = 0; k < kExitWeightNodes; ++k)
    table[k] = w.at(static_cast<float>(k) / (kExitWeightNodes - 1));
  return table;
}

ShadingParameters shadingFor(const BakedPlyContents& contents, const ShadingRequest& request) {
  ShadingParameters p;
  p.eta = contents.hasMaterial ? static_cast<float>(contents.baked.eta) : kFallbackEta;
  if (request.eta) p.eta = *request.eta;
  p.etaIsFallback = !contents.hasMaterial && !request.eta && request.mode == ShadingMode::Sss;
  p.exitScale = request.exitModel == ExitModel::Jensen
                    ? static_cast<float>(1.0 / M_PI)
                    : static_cast<float>(exitRadianceScale(p.eta));
  if (request.exitModel == ExitModel::Calibrated && contents.hasMaterial)
    p.exitWeight = exitWeightTable(contents.baked, p.eta);
  p.exitLobe = request.exitModel == ExitModel::Auto && request.mode == ShadingMode::Sss &&
               contents.hasExitSlope;
  if (p.exitLobe) {
    const ExitLobe lobe(p.eta);
    p.lobeMoment0 = float(lobe.moment(0));
    p.lobeMoment1 = float(lobe.moment(1));
  }
  if (request.mode == ShadingMode::Brdf) {
    if (request.albedo) {
      p.albedo = *request.albedo;
    } else if (contents.hasMaterial) {
      p.albedo = halfSpaceAlbedo(contents.baked, p.eta);
    } else {
      p.albedo = glm::vec3(kFallbackAlbedo);
      p.albedoIsFallback = true;
    }
  }
  const MeshReport& report = contents.report;
  const bool closedAndConsistent =
      report.boundaryEdges == 0 && report.misorientedEdges == 0 && report.nonManifoldEdges == 0;
  p.cullBackFaces =
      request.cull == CullMode::Back || (request.cull == CullMode::Auto && closedAndConsistent);
  const bool unscattered =
      request.unscattered == UnscatteredDrawing::On ||
      (request.unscattered == UnscatteredDrawing::Auto && contents.baked.unscatteredTraced);
  // The mode and the culling it also needs are the renderer's to check
  // (ShadingOptions::drawsUnscattered).
  if (unscattered && contents.hasMaterial && contents.hasUnits) {
    const BakedMesh& b = contents.baked;
    p.unscatteredSigmaT = glm::vec3((b.sigmaA + b.sigmaSPrime) * b.mmPerUnit);
  }
  return p;
}

std::string missingBakedValues(const BakedPlyContents& contents, ShadingMode mode) {
  if (mode == ShadingMode::Sss && !contents.hasExitance) return channels("exitance");
  if (mode == ShadingMode::Irradiance && !contents.hasIrradiance) return channels("irradiance");
  return {};
}

RenderMesh renderMeshFor(const BakedMesh& baked, ShadingMode mode, bool exitLobe) {
  RenderMesh mesh;
  mesh.positions = baked.mesh.positions;
  mesh.normals = baked.mesh.normals;
  if (mode == ShadingMode::Sss) mesh.values = baked.exitance;
  if (mode == ShadingMode::Sss && exitLobe) mesh.exitSlopes = baked.exitSlope;
  if (mode == ShadingMode::Irradiance) mesh.values = baked.irradiance;
  mesh.indices.reserve(baked.mesh.triangles.size() * 3);
  for (const glm::uvec3& t : baked.mesh.triangles)
    mesh.indices.insert(mesh.indices.end(), {t.x, t.y, t.z});
  return mesh;
}

}  // namespace sss
