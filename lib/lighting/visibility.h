// Fresnel-transmitted irradiance with visibility: Li & Guo Eq. 6 with soft shadows,
//   E(x) = integral over the hemisphere of (1 - F_r(eta, w.n)) L(w) (w.n) V(x, w) dw,
// estimated per vertex by Monte Carlo with Embree occlusion rays, with (w.n) and F_r's argument
// those of the vertex's facets, averaged by area (mesh/triangle_mesh.h, VertexFacets): the light
// the surface around the vertex receives, which at a crease is not the light its averaged normal
// would (visibility_vertex_estimator.h).
//
// Estimator: the ratio of the unblocked samples' sum to all samples' sum times the light with
// nothing in the way, known in closed form (visibility_vertex_estimator.h): the rays measure only
// what is blocked, so a convex part needs none. The samples: two techniques combined by multiple
// importance sampling (Veach & Guibas 1995, multi-sample balance heuristic): half the samples from
// the environment (EnvironmentSampler, lib/envmap/environment_sampler.h: piecewise constant over
// cubemap texels, probability proportional to luminance x solid angle, so a small bright sun is
// found by every vertex facing it) and half cosine-weighted over the hemisphere (so dim, wide parts
// of the sky are not starved). Each sample contributes f(w) / (n_env p_env(w) + n_cos p_cos(w)),
// which is bounded where either technique fits the integrand: no fireflies from a sun. Radiance is
// the cubemap texel a direction falls in (piecewise constant, the same function the sampling pdf
// describes), so the estimate converges to the texel sum an irradiance cubemap computes. Sample
// points are Cranley-Patterson-rotated Hammersley sets seeded per vertex (Pcg32(seed, vertex)):
// stratified, and identical for any thread count.
//
// Ray origins: the vertex moved along its normal by 2e-5 of its largest coordinate magnitude
// (or of the mesh's extent, if larger), with tnear the same distance, so that float rounding
// never makes a ray hit the triangles around its own vertex. On a convex part no ray with
// w.n > 0 can re-enter the mesh (the area-weighted normal lies in the vertex's normal cone), so
// there visibility changes nothing; see tests/lighting/visibility_test.cpp.
//
// Rays: Embree (medium-quality BVH), each vertex's rays as one incoherent stream
// (rtcOccluded1M): on the dragons this beats single rays and packets of 8 or 16, and the
// high-quality build costs more than it saves (docs/tools/sss-bake.md, "Lighting and
// visibility"; tests/bench/results/bake).
//
// Units: E has the units of the cubemap's radiance times steradians; positions in any unit.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/run_context.h"
#include "envmap/cubemap.h"
#include "lighting/cosine_hits.h"
#include "lighting/visibility_pilot.h"
#include "material/directional_albedo_weight.h"

namespace sss {

class TriangleScene;  // raytrace/triangle_scene.h

struct VisibilityOptions {
  int samples = 64;                       // rays per vertex (half environment, half cosine); >= 2
  RunContext run;                         // quiet by default: no progress bar
  VisibilityPilotOptions pilot{0, 0, 0};  // replicas 0: no pilot
  // The directional entry (material/directional_albedo_weight.h): when set, the full pass also
  // returns E_w, the same samples weighted by w(cosine) (VisibilityReport::entryWeighted). Not
  // owned.
  const DirectionalAlbedoWeight* entry = nullptr;
  // The ratio estimator against the light with nothing in the way (visibility_vertex_estimator.h,
  // unoccluded_intake.h): the rays estimate only the blocked fraction. false: the plain sum of
  // the unblocked samples (the tests' comparison).
  bool ratioToUnoccluded = true;
  // Keep the cosine rays that meet the mesh (CosineHits) when the full pass's cosine samples per
  // vertex are at most this many (their memory and the gather's work grow with them); 0: never.
  int keepCosineHitsUpTo = 0;
  // The mesh's ray scene (TriangleSceneOptions::surfaceRays over these positions and triangles)
  // where the caller has one for its other stages; null: built here. Not owned.
  const TriangleScene* scene = nullptr;
  // Called with the pilot (if one runs) before the full pass; returns the rays per vertex to use
  // (>= 2). Empty: `samples`.
  std::function<int(const VisibilityPilot&)> chooseSamples;
};

struct VisibilityReport {
  double buildSeconds = 0.0;       // Embree BVH
  double traceSeconds = 0.0;       // sampling and occlusion rays
  double unoccludedSeconds = 0.0;  // the unoccluded light's cubemaps (ratioToUnoccluded)
  uint64_t rays = 0;               // occlusion rays traced (samples with w.n > 0)
  double occludedFraction = 0.0;   // of the traced rays
  // Root mean square over lit vertices of the estimated relative standard error of the
  // luminance of E (per-technique sample variance; stratification makes it an overestimate).
  double relativeStdError = 0.0;
  int samples = 0;                       // rays per vertex of the full pass
  VisibilityPilot pilot;                 // empty if none ran
  std::vector<glm::vec3> entryWeighted;  // E_w per vertex when VisibilityOptions::entry is set
  CosineHits cosineHits;                 // per keepCosineHitsUpTo, else empty
};

// Per-vertex transmitted irradiance with shadows from the mesh itself. `normals` are unit vertex
// normals pointing out; `eta` the material's relative index. Throws Error on bad sizes/indices.
std::vector<glm::vec3> transmittedIrradianceWithVisibility(std::span<const glm::vec3> positions,
                                                           std::span<const glm::vec3> normals,
                                                           std::span<const glm::uvec3> triangles,
                                                           const Cubemap& radiance, float eta,
                                                           const VisibilityOptions& options,
                                                           VisibilityReport* report = nullptr);

}  // namespace sss
