#include "bake/interreflection.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include <glm/geometric.hpp>

#include "core/barycentric.h"
#include "core/bounds.h"
#include "core/error.h"
#include "core/parallel.h"
#include "core/random.h"
#include "core/sampling.h"
#include "optics/fresnel.h"
#include "raytrace/triangle_scene.h"

namespace sss {

InterreflectionGather::InterreflectionGather(std::span<const glm::vec3> positions,
                                             std::span<const glm::vec3> normals,
                                             std::span<const glm::uvec3> triangles,
                                             const Cubemap& radiance, float eta,
                                             const InterreflectionOptions& options) {
  const std::size_t n = positions.size();
  if (normals.size() != n || triangles.empty()) fail("", "interreflection: empty mesh");
  if (options.rays < 1) fail("", "interreflection: at least one ray per vertex");
  const TriangleScene scene(positions, triangles);
  const float extent = boundsOf(positions).longestSide();
  const float exitScale = float(exitRadianceScale(eta));
  const DirectionalAlbedoWeight diffuse;
  const DirectionalAlbedoWeight& weight = options.entry ? *options.entry : diffuse;
  const uint32_t rays = uint32_t(options.rays);
  const float perRay = float(M_PI / options.rays);
  std::vector<std::vector<Hit>> perVertex(n);
  std::atomic<uint64_t> blocked{0};
  parallelFor(n, options.threads, 64, [&](std::size_t begin, std::size_t end) {
    uint64_t count = 0;
    for (std::size_t v = begin; v < end; ++v) {
      Pcg32 rng(options.seed, v);
      const float r0 = rng.uniform(), r1 = rng.uniform();
      const glm::vec3 nv = normals[v], p = positions[v];
      glm::vec3 tangent, bitangent;
      orthonormalBasis(nv, tangent, bitangent);
      // The visibility stage's offset (visibility_vertex_estimator.cpp), so that both call the
      // same directions blocked.
      const float offset = 2e-5f * std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z), extent});
      for (uint32_t j = 0; j < rays; ++j) {
        float u1, u2;
        hammersley(j, rays, r0, r1, u1, u2);
        const glm::vec3 local = sampleCosineHemisphereConcentric(u1, u2);
        if (local.z <= 0.0f) continue;
        const glm::vec3 w = glm::normalize(local.x * tangent + local.y * bitangent + local.z * nv);
        const SceneHit hit = scene.intersect(p + offset * nv, w, offset);
        if (!hit.hit) continue;
        ++count;
        const glm::uvec3 tri = triangles[hit.triangle];
        const glm::vec3 at = p + offset * nv + hit.t * w;
        const glm::vec3 bary(
            barycentricWeights(at, positions[tri.x], positions[tri.y], positions[tri.z]));
        const glm::vec3 nh = glm::normalize(bary.x * normals[tri.x] + bary.y * normals[tri.y] +
                                            bary.z * normals[tri.z]);
        // The cosine at the hit by its smooth normal, as B's exit model is; where a facet seen
        // from its front has a smooth normal turned away (the rim of a concavity), by the facet's.
        float muH = -glm::dot(w, nh);
        if (!(muH > 0.0f)) muH = -glm::dot(w, hit.faceNormal);
        if (!(muH > 0.0f)) continue;  // the back of a surface: no light leaves towards v
        const glm::vec3 entry = perRay * fresnelTransmittance(local.z, eta) * weight.at(local.z);
        const glm::vec3 mirror = w + 2.0f * muH * nh;
        perVertex[v].push_back({tri, bary, entry * fresnelTransmittance(muH, eta) * exitScale,
                                entry * fresnelDielectric(muH, eta) * radiance.sample(mirror)});
      }
    }
    blocked += count;
  });
  offsets_.assign(n + 1, 0);
  for (std::size_t v = 0; v < n; ++v) offsets_[v + 1] = offsets_[v] + uint32_t(perVertex[v].size());
  hits_.reserve(offsets_[n]);
  for (auto& hits : perVertex) hits_.insert(hits_.end(), hits.begin(), hits.end());
  blockedFraction_ = double(blocked) / double(std::max<std::size_t>(n * rays, 1));
}

std::vector<glm::vec3> InterreflectionGather::gather(std::span<const glm::vec3> exitance) const {
  const std::size_t n = offsets_.size() - 1;
  if (exitance.size() != n) fail("", "interreflection: one exitance per vertex needed");
  std::vector<glm::vec3> e(n, glm::vec3(0.0f));
  for (std::size_t v = 0; v < n; ++v) {
    for (uint32_t k = offsets_[v]; k < offsets_[v + 1]; ++k) {
      const Hit& h = hits_[k];
      const glm::vec3 b = h.barycentric.x * exitance[h.vertices.x] +
                          h.barycentric.y * exitance[h.vertices.y] +
                          h.barycentric.z * exitance[h.vertices.z];
      e[v] += h.exitWeight * b + h.reflection;
    }
  }
  return e;
}

namespace {

// Relative RMS of a - b over all vertices and channels.
double relativeChange(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const glm::dvec3 d = glm::dvec3(a[i]) - glm::dvec3(b[i]);
    num += glm::dot(d, d);
    den += glm::dot(glm::dvec3(b[i]), glm::dvec3(b[i]));
  }
  return den > 0.0 ? std::sqrt(num / den) : 0.0;
}

}  // namespace

BounceResult iterateInterreflection(
    const InterreflectionGather& gather, std::span<const glm::vec3> direct,
    const std::function<std::vector<glm::vec3>(std::span<const glm::vec3>)>& transport,
    int maxBounces, double tolerance) {
  constexpr int kAutoBounceLimit = 64;
  BounceResult r;
  r.irradiance.assign(direct.begin(), direct.end());
  r.exitance = transport(r.irradiance);
  const int limit = maxBounces > 0 ? maxBounces : kAutoBounceLimit;
  for (int bounce = 0; bounce < limit; ++bounce) {
    const std::vector<glm::vec3> indirect = gather.gather(r.exitance);
    for (std::size_t v = 0; v < direct.size(); ++v) r.irradiance[v] = direct[v] + indirect[v];
    std::vector<glm::vec3> next = transport(r.irradiance);
    r.change = relativeChange(next, r.exitance);
    r.exitance = std::move(next);
    r.bounces = bounce + 1;
    if (maxBounces <= 0 && r.change < tolerance) break;
  }
  return r;
}

}  // namespace sss
