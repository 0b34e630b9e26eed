// One vertex's estimate of the transmitted irradiance with visibility (visibility.h): the
// multiple-importance-sampling estimator over environment and cosine samples, traced as one
// stream of Embree occlusion rays. Private to lib/lighting.
// The integrand is the light the vertex's facets take in (facet_light.h).
//
// With an UnoccludedIntake (unoccluded_intake.h), the estimate is the ratio estimator against
// the light with nothing in the way, per channel
//   E = U * Y / X,   Y = sum over unblocked samples of f / p,   X = the same over all samples,
// U = sum_f share_f T(n_f) known in closed form: the samples estimate only the fraction of the
// light that is blocked, so a vertex with nothing in the way is exact at any ray count (Y = X),
// one in a deep concavity as sure of its little light as the plain sum (Y and X share their
// noise), and in between the noise is that of the blocked fraction (Cochran, "Sampling
// Techniques", 1977, ch. 6). Its bias is
// O(1/n) of X's relative variance, which the environment's importance sampling keeps small
// (tests/lighting/visibility_test.cpp measures it in a concavity at 16 rays).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "core/random.h"
#include "envmap/environment_sampler.h"
#include "lighting/cosine_hits.h"
#include "lighting/facet_light.h"
#include "lighting/unoccluded_intake.h"
#include "material/directional_albedo_weight.h"
#include "mesh/triangle_mesh.h"
#include "raytrace/triangle_scene.h"

namespace sss {

struct VertexEstimate {
  glm::vec3 irradiance;
  glm::vec3 entryWeighted;  // the same samples weighted by the directional entry (E_w), if any
  float relativeVariance;   // per-technique estimate of the luminance's; < 0: unlit
  uint32_t rays, occluded;
};

// Everything one vertex's estimate needs, and per-thread buffers: one estimator per thread.
class VertexEstimator {
 public:
  // `extent`: the mesh's longest bounding-box side, a floor for the ray offset's scale.
  // `unoccluded`: null for the plain sum, else the ratio estimator (above).
  VertexEstimator(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                  const VertexFacets& facets, const EnvironmentSampler& sampler,
                  const TriangleScene& scene, float eta, float extent,
                  const DirectionalAlbedoWeight* entry, const UnoccludedIntake* unoccluded)
      : positions_(positions),
        normals_(normals),
        facets_(facets),
        sampler_(sampler),
        scene_(scene),
        entry_(entry),
        unoccluded_(unoccluded),
        eta_(eta),
        extent_(extent) {}

  // E at vertex v from `samples` rays (half environment, rounded up, half cosine); rng supplies
  // the four rotations of the two Hammersley sets.
  VertexEstimate estimate(std::size_t v, int samples, Pcg32& rng);
  // With keep, estimate() traces the cosine samples for their nearest hit (the environment's as
  // before) and keeps those that meet the mesh: cosineHits() after each estimate.
  void keepCosineHits(bool keep) { keepCosineHits_ = keep; }
  const std::vector<CosineHit>& cosineHits() const { return cosineHits_; }

 private:
  struct Candidate {
    glm::vec3 contribution;  // if unoccluded
    glm::vec3 entryScale;    // E_w's contribution over E's (the directional entry's w)
    int technique;           // 0: environment, 1: cosine
  };
  // Fills rays_ and candidates_ with the samples that can contribute, and traces them.
  void traceCandidates(std::size_t v, uint32_t envCount, uint32_t cosCount, Pcg32& rng);
  // traceCandidates' tracing when the cosine samples' hits are kept (keepCosineHits).
  void traceKeepingCosineHits();

  std::span<const glm::vec3> positions_, normals_;
  const VertexFacets& facets_;
  const EnvironmentSampler& sampler_;
  const TriangleScene& scene_;
  const DirectionalAlbedoWeight* entry_;  // null: no E_w
  const UnoccludedIntake* unoccluded_;    // null: the plain sum of the unblocked samples
  float eta_, extent_;
  std::vector<OcclusionRay> rays_;
  std::vector<Candidate> candidates_;
  std::vector<char> blocked_;
  bool keepCosineHits_ = false;
  std::vector<OcclusionRay> cosineRays_;
  std::vector<glm::vec3> cosineWeights_;
  std::vector<int> cosineRayIndex_;     // per kept cosine sample where rays_ holds it
  std::vector<uint32_t> cosineSample_;  // per kept cosine sample its index in the set
  std::vector<SceneHit> sceneHits_;
  std::vector<CosineHit> cosineHits_;
};

}  // namespace sss
