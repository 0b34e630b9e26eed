#include "lighting/visibility_transfer.h"

#include <atomic>
#include <optional>
#include <string>

#include <glm/geometric.hpp>

#include "core/bounds.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/random.h"
#include "core/sampling.h"
#include "irradiance/spherical_harmonics.h"
#include "irradiance/transmitted_cosine.h"
#include "lighting/facet_light.h"
#include "material/directional_albedo_weight.h"
#include "raytrace/triangle_scene.h"

namespace sss {

namespace {

// The seed's stream offset for these rays (core/random.h: each stage its own).
constexpr uint64_t kTransferStream = 0x7e1a5f3b;

// kHat_l,c of the kernel F_t(mu) w_c(mu) mu, per band.
std::vector<glm::vec3> zonalCoefficients(float eta, const DirectionalAlbedoWeight* entry,
                                         int order) {
  const TransmittedCosineKernel kernel(eta);
  std::vector<glm::vec3> out(order + 1);
  for (int l = 0; l <= order; ++l)
    out[l] = entry ? glm::vec3(kernel.weightedZonalCoefficient(
                         l, [&](double mu) { return glm::dvec3(entry->at(float(mu))); }))
                   : glm::vec3(float(kernel.zonalCoefficient(l)));
  return out;
}

// The unoccluded part of vertex v's transfer: sum_f share_f kHat_l Y_lm(n_f).
void addUnoccluded(const VertexFacets& facets, std::size_t v, const glm::vec3& normal,
                   const std::vector<glm::vec3>& zonal, int order, std::vector<float>& basis,
                   std::span<glm::vec3> out) {
  forEachLightFacet(facets, v, normal, [&](const glm::vec3& n, float share) {
    SphericalHarmonics::evaluateBasis(order, n, basis.data());
    for (int l = 0, lm = 0; l <= order; ++l)
      for (int m = -l; m <= l; ++m, ++lm) out[lm] += share * zonal[l] * basis[lm];
  });
}

}  // namespace

VisibilityTransfer visibilityTransfer(std::span<const glm::vec3> positions,
                                      std::span<const glm::vec3> normals,
                                      std::span<const glm::uvec3> triangles, float eta,
                                      const VisibilityTransferOptions& options) {
  const int order = options.order;
  if (order < 0 || order > SphericalHarmonics::kMaxOrder)
    throw Error("relightable transfer: SH order must be in [0, " +
                std::to_string(SphericalHarmonics::kMaxOrder) + "], got " + std::to_string(order));
  if (options.rays < 1) throw Error("relightable transfer: rays per vertex must be >= 1");
  VisibilityTransfer out;
  out.order = order;
  out.count = (order + 1) * (order + 1);
  out.coefficients.assign(positions.size() * out.count, glm::vec3(0.0f));
  const std::vector<glm::vec3> zonal = zonalCoefficients(eta, options.entry, order);
  const VertexFacets facets = lightFacets(positions, normals, triangles);
  std::optional<TriangleScene> own;
  const TriangleScene& scene = givenOrBuilt(options.scene, own, positions, triangles,
                                            TriangleSceneOptions::surfaceRays(options.run.threads));
  const float extent = boundsOf(positions).longestSide();
  const uint32_t n = static_cast<uint32_t>(options.rays);
  std::atomic<uint64_t> blocked{0};
  parallelFor(positions.size(), options.run.threads, 64, [&](std::size_t begin, std::size_t end) {
    std::vector<float> basis(out.count);
    std::vector<OcclusionRay> rays(n);
    std::vector<char> hit;
    uint64_t blockedHere = 0;
    for (std::size_t v = begin; v < end; ++v) {
      const std::span<glm::vec3> t(out.coefficients.data() + v * out.count, out.count);
      addUnoccluded(facets, v, normals[v], zonal, order, basis, t);
      Pcg32 rng(options.run.seed, kTransferStream + v);
      const float r0 = rng.uniform(), r1 = rng.uniform();
      const float offset = surfaceRayOffset(positions[v], extent);
      for (uint32_t i = 0; i < n; ++i) {
        float u1, u2;
        hammersley(i, n, r0, r1, u1, u2);
        rays[i] = {positions[v] + offset * normals[v],
                   sampleFacetCosine(facets, v, normals[v], u1, u2), offset};
      }
      scene.occluded(rays, hit);
      for (uint32_t i = 0; i < n; ++i) {
        if (!hit[i]) continue;
        ++blockedHere;
        // What the direction would have brought, per unit radiance, over the mixture's pdf.
        const FacetIntake intake =
            facetIntake(facets, v, normals[v], rays[i].direction, eta, options.entry);
        if (intake.cosinePdf <= 0.0f) continue;
        const glm::vec3 weight =
            (options.entry ? intake.entryWeighted : glm::vec3(intake.transmitted)) /
            (intake.cosinePdf * float(n));
        SphericalHarmonics::evaluateBasis(order, rays[i].direction, basis.data());
        for (int lm = 0; lm < out.count; ++lm) t[lm] -= weight * basis[lm];
      }
    }
    blocked += blockedHere;
  });
  out.blockedFraction =
      positions.empty() ? 0.0 : double(blocked) / (double(positions.size()) * double(n));
  return out;
}

std::vector<glm::vec3> directionalIrradiance(std::span<const glm::vec3> positions,
                                             std::span<const glm::vec3> normals,
                                             std::span<const glm::uvec3> triangles, float eta,
                                             const DirectionalAlbedoWeight* entry,
                                             std::span<const DirectionalLight> lights,
                                             const RunContext& run) {
  if (lights.empty() || positions.empty()) return std::vector<glm::vec3>(positions.size());
  const TriangleScene scene(positions, triangles, TriangleSceneOptions::surfaceRays(run.threads));
  return DirectionalShadows(positions, normals, triangles, eta, entry, run)
      .irradiance(lights, scene);
}

DirectionalShadows::DirectionalShadows(std::span<const glm::vec3> positions,
                                       std::span<const glm::vec3> normals,
                                       std::span<const glm::uvec3> triangles, float eta,
                                       const DirectionalAlbedoWeight* entry, const RunContext& run)
    : positions_(positions),
      normals_(normals),
      triangles_(triangles),
      eta_(eta),
      entry_(entry),
      run_(run),
      facets_(lightFacets(positions, normals, triangles)) {}

std::vector<glm::vec3> DirectionalShadows::irradiance(std::span<const DirectionalLight> lights,
                                                      const TriangleScene& scene) const {
  std::vector<glm::vec3> e(positions_.size(), glm::vec3(0.0f));
  if (lights.empty() || positions_.empty()) return e;
  requireSceneOfMesh(scene, triangles_);
  const float extent = boundsOf(positions_).longestSide();
  parallelFor(positions_.size(), run_.threads, 256, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) {
      const float offset = surfaceRayOffset(positions_[v], extent);
      for (const DirectionalLight& light : lights) {
        const FacetIntake intake =
            facetIntake(facets_, v, normals_[v], light.direction, eta_, entry_);
        if (intake.transmitted <= 0.0f) continue;
        if (scene.occluded(positions_[v] + offset * normals_[v], light.direction, offset)) continue;
        e[v] += light.irradiance * (entry_ ? intake.entryWeighted : glm::vec3(intake.transmitted));
      }
    }
  });
  return e;
}

}  // namespace sss
