// The light a vertex's facets take in (mesh/triangle_mesh.h, VertexFacets), for the estimators
// that gather light at a vertex over directions: the environment's with visibility
// (visibility_vertex_estimator.h) and the object's own (interreflection.h). A per-vertex value
// stands for the facets around the vertex (the reference's barycentric tally, and the surface the
// light enters), not for a plane at the averaged normal: on a box's edge that normal points 45
// degrees from both faces, and under a sun it can face away while one face is lit
// (tests/bench/concavity_study.cpp: with the normal's light the box's terminator edges read 0.63x
// and 0.85x the reference's radiance; docs/physics.md, "Light on the facets around a vertex").
//
//   factor(w) = sum over facets f of share_f T(eta, w . n_f) (w . n_f)+     (Li & Guo Eq. 6)
//
// and its sampler: a facet by share, then a cosine-weighted direction about its normal (pdf the
// shares' mixture of cosine lobes), which keeps factor / pdf <= pi.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "core/sampling.h"
#include "material/directional_albedo_weight.h"
#include "mesh/triangle_mesh.h"
#include "optics/fresnel.h"

namespace sss {

// Vertices whose facets all lie within 30 degrees of the normal take the light at the normal (one
// facet, at a single facet's cost). Creases of more (a box's edges and corners: 45 and 55 degrees;
// a slab's rim) take their facets', those within 15 degrees of each other grouped (a box's edge has
// two groups, a scan's noisy crease a few). The facets' light differs from the normal's by about
// E tilt^2 / 2 where the light is smooth (a few percent at 15 degrees), by up to the tilt's share
// of E at a sun's terminator. At 30 degrees 9 % of the scanned dragon's 100K vertices take their
// facets' light; at 8 degrees 45 % would, for 1.25-1.5x its default bake and nothing measurable
// (docs/physics.md, "Light on the facets around a vertex"; docs/performance.md, "What each part
// costs").
inline constexpr double kSmoothFacetCosine = 0.8660254;  // cos(30 degrees)
inline constexpr double kFacetGroupCosine = 0.9659258;   // cos(15 degrees)

// The facets the estimators take light over (mesh/triangle_mesh.h).
inline VertexFacets lightFacets(std::span<const glm::vec3> positions,
                                std::span<const glm::vec3> normals,
                                std::span<const glm::uvec3> triangles) {
  return vertexFacets(positions, normals, triangles, kSmoothFacetCosine, kFacetGroupCosine);
}

// Calls add(n_f, share_f) for each of vertex v's facets; a vertex without facets (no triangle of
// any area) takes its normal as its one facet, add(normal, 1).
template <typename Add>
inline void forEachLightFacet(const VertexFacets& facets, std::size_t v, const glm::vec3& normal,
                              Add&& add) {
  const uint32_t first = facets.begin[v], last = facets.begin[v + 1];
  if (first == last) add(normal, 1.0f);
  for (uint32_t k = first; k < last; ++k) add(facets.normals[k], facets.shares[k]);
}

struct FacetIntake {
  float transmitted = 0.0f;       // factor(w)
  glm::vec3 entryWeighted{0.0f};  // the same with each facet's term times the entry's w(w . n_f)
  float cosinePdf = 0.0f;         // sampleFacetCosine's pdf of w: sum share_f (w . n_f)+ / pi
};

// entry: null for none (entryWeighted stays 0). A vertex without facets (no triangle of any area)
// takes its normal as its one facet.
inline FacetIntake facetIntake(const VertexFacets& facets, std::size_t v, const glm::vec3& normal,
                               const glm::vec3& w, float eta,
                               const DirectionalAlbedoWeight* entry) {
  FacetIntake in;
  const auto add = [&](const glm::vec3& n, float share) {
    const float c = glm::dot(w, n);
    if (c <= 0.0f) return;
    const float t = share * fresnelTransmittance(c, eta) * c;
    in.transmitted += t;
    if (entry) in.entryWeighted += t * entry->at(c);
    in.cosinePdf += share * c * static_cast<float>(1.0 / M_PI);
  };
  forEachLightFacet(facets, v, normal, add);
  return in;
}

// A direction from the facets' mixture of cosine lobes: u1 picks the facet by share and is
// rescaled within its interval, so (u1, u2)'s stratification carries over to each lobe.
inline glm::vec3 sampleFacetCosine(const VertexFacets& facets, std::size_t v,
                                   const glm::vec3& normal, float u1, float u2) {
  glm::vec3 axis = normal;
  const uint32_t first = facets.begin[v], last = facets.begin[v + 1];
  for (uint32_t k = first; k < last; ++k) {
    const float share = facets.shares[k];
    axis = facets.normals[k];
    if (u1 < share || k + 1 == last) {
      u1 = std::fmin(u1 / share, 0x1.fffffep-1f);
      break;
    }
    u1 -= share;
  }
  glm::vec3 tangent, bitangent;
  orthonormalBasis(axis, tangent, bitangent);
  const glm::vec3 local = sampleCosineHemisphereConcentric(u1, u2);
  return glm::normalize(local.x * tangent + local.y * bitangent + local.z * axis);
}

}  // namespace sss
