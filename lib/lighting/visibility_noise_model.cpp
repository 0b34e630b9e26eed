#include "lighting/visibility_noise_model.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <tuple>
#include <vector>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/parallel.h"
#include "material/diffusion_profile.h"
#include "mesh/vertex_grid.h"

namespace sss {

namespace {

// R_d tabulated on [0, radius] (linear interpolation): the weight sums evaluate it millions of
// times. Entry 0 at half a step, for profiles singular at r = 0 (Burley).
class TabulatedProfile {
 public:
  TabulatedProfile(const DiffusionProfile& profile, double radius)
      : step_(radius / kEntries), table_(kEntries + 2) {
    for (int k = 0; k < kEntries + 2; ++k)
      table_[k] = profile.evaluate(k == 0 ? 0.5 * step_ : k * step_);
  }
  glm::dvec3 operator()(double r) const {
    const double x = r / step_;
    const int j = static_cast<int>(x);
    const double f = x - j;
    return (1.0 - f) * table_[j] + f * table_[j + 1];
  }

 private:
  static constexpr int kEntries = 4096;
  double step_;
  std::vector<glm::dvec3> table_;
};

// Per pilot vertex: the predicted variance of B at both levels, |B|^2, and N_eff.
struct PilotVertexTerms {
  std::vector<double> coarse, fine, denominator, effective;
};

PilotVertexTerms pilotVertexTerms(const VisibilityPilot& pilot,
                                  std::span<const glm::vec3> positionsMm,
                                  std::span<const float> areasMm2,
                                  const DiffusionProfile& profile) {
  const double radius = profile.radiusContaining(0.999);
  const TabulatedProfile table(profile, radius);
  const VertexGrid grid(positionsMm, radius);
  const std::size_t m = pilot.vertices.size();
  PilotVertexTerms t{std::vector<double>(m), std::vector<double>(m), std::vector<double>(m),
                     std::vector<double>(m)};
  parallelFor(m, 0, 16, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      const uint32_t o = pilot.vertices[k];
      const glm::vec3 po = positionsMm[o];
      const glm::dvec3 self = profile.integrateDisc(std::sqrt(areasMm2[o] / M_PI));
      glm::dvec3 w1 = self, w2 = self * self;
      grid.forEachNear(po, [&](uint32_t v) {
        if (v == o) return;
        const glm::vec3 d = positionsMm[v] - po;
        const double r = std::sqrt(static_cast<double>(glm::dot(d, d)));
        if (r >= radius) return;
        const glm::dvec3 w = table(r) * static_cast<double>(areasMm2[v]);
        w1 += w;
        w2 += w * w;
      });
      const glm::dvec3 e(pilot.irradiance[k]);
      t.coarse[k] = glm::dot(glm::dvec3(pilot.coarseVariance[k]), w2);
      t.fine[k] = glm::dot(glm::dvec3(pilot.fineVariance[k]), w2);
      t.denominator[k] = glm::dot(e * w1, e * w1);
      t.effective[k] = w2.g > 0.0 ? w1.g * w1.g / w2.g : 1.0;
    }
  });
  return t;
}

}  // namespace

VisibilityNoiseModel visibilityNoiseModel(const VisibilityPilot& pilot,
                                          std::span<const glm::vec3> positionsMm,
                                          std::span<const float> areasMm2,
                                          const DiffusionProfile& profile) {
  VisibilityNoiseModel model;
  if (pilot.vertices.empty() || positionsMm.empty()) return model;
  if (areasMm2.size() != positionsMm.size()) fail("", "noise model: one area per vertex required");
  const PilotVertexTerms t = pilotVertexTerms(pilot, positionsMm, areasMm2, profile);
  const std::size_t m = pilot.vertices.size();
  double coarseSum = 0.0, fineSum = 0.0, den = 0.0, neff = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    coarseSum += t.coarse[k];
    fineSum += t.fine[k];
    den += t.denominator[k];
    neff += t.effective[k];
  }
  model.fineRays = pilot.fineRays;
  model.variance = den > 0.0 ? fineSum / den : 0.0;
  // Rate between the levels, kept within plain Monte Carlo (1) and stratified sampling of a
  // discontinuity in 2D (1.5) against the noise of the estimate.
  model.rate =
      coarseSum > 0.0 && fineSum > 0.0
          ? std::clamp(std::log(coarseSum / fineSum) /
                           std::log(static_cast<double>(pilot.fineRays) / pilot.coarseRays),
                       1.0, 1.5)
          : 1.0;
  model.meanEffectiveVertices = neff / static_cast<double>(m);
  return model;
}

double VisibilityNoiseModel::irradianceErrorAt(const VisibilityPilot& pilot, int samples) const {
  double eVariance = 0.0, eSquare = 0.0;
  for (std::size_t k = 0; k < pilot.vertices.size(); ++k) {
    const glm::dvec3 var(pilot.fineVariance[k]), e(pilot.irradiance[k]);
    eVariance +=
        (var.r + var.g + var.b) * std::pow(static_cast<double>(pilot.fineRays) / samples, rate);
    eSquare += glm::dot(e, e);
  }
  return eSquare > 0.0 ? std::sqrt(eVariance / eSquare) : 0.0;
}

int chooseVisibilitySamples(const VisibilityNoiseModel& model, double budget, int maxSamples) {
  if (!(model.variance > 0.0)) return kMinAutoSamples;
  if (!(budget > 0.0)) return maxSamples;
  // errorAt(n) = budget solved for n, then rounded up to whole strata of 16.
  const double exact =
      model.fineRays * std::pow(model.variance / (budget * budget), 1.0 / model.rate);
  if (!(exact < maxSamples)) return maxSamples;
  const int rounded = static_cast<int>(std::ceil(exact / kAutoSampleStep)) * kAutoSampleStep;
  return std::clamp(rounded, kMinAutoSamples, maxSamples);
}

int maxAutoSamples(std::size_t vertices) {
  const double perVertex = kAutoRayBudget / static_cast<double>(std::max<std::size_t>(vertices, 1));
  const int steps =
      static_cast<int>(std::min<double>(perVertex, kMaxAutoSamplesCoarse)) / kAutoSampleStep;
  return std::max(kMaxAutoSamples, steps * kAutoSampleStep);
}

}  // namespace sss
