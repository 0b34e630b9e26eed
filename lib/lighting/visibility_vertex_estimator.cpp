#include "lighting/visibility_vertex_estimator.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "core/luminance.h"
#include "core/sampling.h"
#include "lighting/facet_light.h"
#include "optics/fresnel.h"

namespace sss {

void VertexEstimator::traceCandidates(std::size_t v, uint32_t envCount, uint32_t cosCount,
                                      Pcg32& rng) {
  const float nEnv = static_cast<float>(envCount), nCos = static_cast<float>(cosCount);
  const glm::vec3 n = normals_[v];
  const glm::vec3 p = positions_[v];
  const float r0 = rng.uniform(), r1 = rng.uniform(), r2 = rng.uniform(), r3 = rng.uniform();
  const float offset = surfaceRayOffset(p, extent_);
  const glm::vec3 origin = p + offset * n;

  // Candidate rays: direction and unoccluded contribution f / (n_env p_env + n_cos p_cos); the
  // candidate's index, or -1 where the sample cannot contribute.
  rays_.clear();
  candidates_.clear();
  const auto add = [&](const FacetIntake& facet, const glm::vec3& w, const glm::vec3& l,
                       float pdfEnv, int tech) {
    const glm::vec3 f = facet.transmitted * l;
    if (f.r <= 0.0f && f.g <= 0.0f && f.b <= 0.0f) return -1;
    rays_.push_back({origin, w, offset, std::numeric_limits<float>::infinity()});
    candidates_.push_back({f / (nEnv * pdfEnv + nCos * facet.cosinePdf),
                           facet.entryWeighted / facet.transmitted, tech});
    return static_cast<int>(candidates_.size() - 1);
  };
  // The cosine technique samples the facets' mixture of cosine lobes (facet_light.h); the
  // environment's reaches every direction the facets face.
  for (uint32_t j = 0; j < envCount; ++j) {
    float u1, u2;
    hammersley(j, envCount, r0, r1, u1, u2);
    const EnvironmentSampler::Sample s = sampler_.sample(u1, u2);
    add(facetIntake(facets_, v, n, s.direction, eta_, entry_), s.direction, s.radiance, s.pdf, 0);
  }
  cosineRays_.clear();
  cosineWeights_.clear();
  cosineRayIndex_.clear();
  cosineSample_.clear();
  for (uint32_t j = 0; j < cosCount; ++j) {
    float u1, u2;
    hammersley(j, cosCount, r2, r3, u1, u2);
    const glm::vec3 w = sampleFacetCosine(facets_, v, n, u1, u2);
    const FacetIntake facet = facetIntake(facets_, v, n, w, eta_, entry_);
    const int candidate = add(facet, w, sampler_.radiance(w), sampler_.pdf(w), 1);
    if (!keepCosineHits_ || !(facet.transmitted > 0.0f)) continue;
    // Kept for the gather: every sample the facets take light in, with the gather's weight (with
    // diffuse entry, w = 1, the sum of the facets' terms times 1, which is `transmitted`, summed
    // in the same order), and where rays_ holds it (-1: not yet, a sample without light).
    cosineWeights_.push_back((entry_ ? facet.entryWeighted : glm::vec3(facet.transmitted)) /
                             facet.cosinePdf);
    cosineRays_.push_back({origin, w, offset, std::numeric_limits<float>::infinity()});
    cosineRayIndex_.push_back(candidate);
    cosineSample_.push_back(j);
  }
  if (keepCosineHits_)
    traceKeepingCosineHits();
  else
    scene_.occluded(rays_, blocked_);
}

// The kept cosine samples: those without light (no candidate) are traced as occlusion rays after
// the candidates' (the gather needs them where the sky is black too), and the blocked ones again
// for their nearest hit (a second, smaller stream: nearest-hit rays cost more than occlusion
// rays, and most rays are not blocked).
void VertexEstimator::traceKeepingCosineHits() {
  const std::size_t candidates = rays_.size();
  for (std::size_t k = 0; k < cosineRays_.size(); ++k) {
    if (cosineRayIndex_[k] >= 0) continue;
    cosineRayIndex_[k] = static_cast<int>(rays_.size());
    rays_.push_back(cosineRays_[k]);
  }
  scene_.occluded(rays_, blocked_);
  std::size_t kept = 0;
  for (std::size_t k = 0; k < cosineRays_.size(); ++k) {
    if (!blocked_[static_cast<std::size_t>(cosineRayIndex_[k])]) continue;
    cosineRays_[kept] = cosineRays_[k];
    cosineSample_[kept] = cosineSample_[k];
    cosineWeights_[kept++] = cosineWeights_[k];
  }
  cosineRays_.resize(kept);
  blocked_.resize(candidates);  // the estimate reads the candidates' only
  scene_.intersect(cosineRays_, sceneHits_);
  cosineHits_.clear();
  for (std::size_t k = 0; k < kept; ++k)
    if (sceneHits_[k].hit)
      cosineHits_.push_back({cosineRays_[k].direction, cosineWeights_[k], sceneHits_[k].t,
                             sceneHits_[k].triangle, cosineSample_[k]});
}

namespace {

// Per channel, the ratio estimate U Y / X (visibility_vertex_estimator.h); Y where X is 0.
glm::vec3 ratioToUnoccluded(const glm::vec3& unoccluded, const glm::dvec3& visible,
                            const glm::dvec3& all) {
  glm::vec3 e;
  for (int c = 0; c < 3; ++c)
    e[c] = all[c] > 0.0 ? float(unoccluded[c] * (visible[c] / all[c])) : float(visible[c]);
  return e;
}

}  // namespace

VertexEstimate VertexEstimator::estimate(std::size_t v, int samples, Pcg32& rng) {
  const uint32_t cosCount = static_cast<uint32_t>(cosineSamplesOf(samples));
  const uint32_t envCount = static_cast<uint32_t>(samples) - cosCount;
  traceCandidates(v, envCount, cosCount, rng);

  VertexEstimate result{glm::vec3(0.0f), glm::vec3(0.0f), -1.0f,
                        static_cast<uint32_t>(candidates_.size()), 0};
  glm::dvec3 visible(0.0), all(0.0), visibleW(0.0), allW(0.0);
  for (std::size_t k = 0; k < candidates_.size(); ++k) {
    const glm::dvec3 c(candidates_[k].contribution);
    const glm::dvec3 cw = entry_ ? c * glm::dvec3(candidates_[k].entryScale) : glm::dvec3(0.0);
    all += c;
    allW += cw;
    if (blocked_[k]) {
      ++result.occluded;
      continue;
    }
    visible += c;
    visibleW += cw;
  }
  // The ratio's residual per sample, y - R x (R = Y / X in luminance), carries its noise to first
  // order: Var(E) / E^2 = Var(sum of residuals) / Y^2. The direct sum's residual is y itself.
  const double yVisible = luminance(glm::vec3(visible)), yAll = luminance(glm::vec3(all));
  const double ratio = unoccluded_ && yAll > 0.0 ? yVisible / yAll : 0.0;
  double sum[2] = {0.0, 0.0}, sumSq[2] = {0.0, 0.0};
  for (std::size_t k = 0; k < candidates_.size(); ++k) {
    const double x = luminance(candidates_[k].contribution);
    const double residual = (blocked_[k] ? 0.0 : x) - ratio * x;
    sum[candidates_[k].technique] += residual;
    sumSq[candidates_[k].technique] += residual * residual;
  }
  // Var(sum of n iid terms) = n Var(term); per technique, zeros included.
  double variance = 0.0;
  const double counts[2] = {static_cast<float>(envCount), static_cast<float>(cosCount)};
  for (int t = 0; t < 2; ++t) {
    if (counts[t] < 2) continue;
    const double mean = sum[t] / counts[t];
    variance += counts[t] / (counts[t] - 1.0) * std::max(0.0, sumSq[t] - counts[t] * mean * mean);
  }
  if (unoccluded_) {
    const UnoccludedIntake::Value u = unoccluded_->at(facets_, v, normals_[v]);
    result.irradiance = ratioToUnoccluded(u.transmitted, visible, all);
    if (entry_) result.entryWeighted = ratioToUnoccluded(u.entryWeighted, visibleW, allW);
  } else {
    result.irradiance = glm::vec3(visible);
    result.entryWeighted = glm::vec3(visibleW);
  }
  if (yVisible > 0.0)
    result.relativeVariance = static_cast<float>(variance / (yVisible * yVisible));
  return result;
}

}  // namespace sss
