// Visibility noise in B, for "auto" samples: how many visibility rays per vertex the bake needs.
//
// The pilot (visibility.h) gives, at a subset of vertices o, E_o and the variance of an m-ray
// estimate per channel at two ray counts. Vertices' estimates are independent (per-vertex seeds),
// so the diffusion sum B_o = sum_i w_oi E_i (w_oi = R_d(r_oi) A_i; the self term the profile
// integrated over the vertex's disc) has Var(B_o) = sum_i w_oi^2 Var(E_i); assuming the variance
// is locally uniform that is Var(E_o) sum_i w_oi^2, with B_o ~ E_o sum_i w_oi: the noise of E
// divided by the effective number of vertices under the kernel, N_eff = (sum w)^2 / sum w^2. The
// relative error of B (sqrt(sum |dB|^2 / sum |B|^2) over vertices and channels, the error the
// benchmarks measure) at n rays is sqrt(variance * (fineRays / n)^rate), the rate (1 = plain
// Monte Carlo, up to 1.5 for stratified sampling of discontinuities) fitted between the pilot's
// two levels. The weight sums run over all mesh vertices within the profile's 99.9% radius of
// each pilot vertex.
#pragma once

#include <cmath>
#include <cstddef>
#include <span>

#include <glm/vec3.hpp>

#include "lighting/visibility.h"

namespace sss {

class DiffusionProfile;  // material/diffusion_profile.h

struct VisibilityNoiseModel {
  int fineRays = 1;
  double variance = 0.0;               // relative variance of B at fineRays rays per vertex
  double rate = 1.0;                   // variance ~ n^-rate
  double meanEffectiveVertices = 0.0;  // mean over pilot vertices of N_eff
  double errorAt(int samples) const {
    return std::sqrt(variance * std::pow(static_cast<double>(fineRays) / samples, rate));
  }
  // Relative RMS noise of E itself at `samples` rays, over the pilot's vertices and channels.
  double irradianceErrorAt(const VisibilityPilot& pilot, int samples) const;
};

VisibilityNoiseModel visibilityNoiseModel(const VisibilityPilot& pilot,
                                          std::span<const glm::vec3> positionsMm,
                                          std::span<const float> areasMm2,
                                          const DiffusionProfile& profile);

// Rays per vertex: the smallest multiple of kAutoSampleStep in [kMinAutoSamples, maxSamples]
// whose predicted error meets `budget` (maxSamples if none does). The floor is the visibility
// estimator's: its ratio to the unoccluded light (visibility_vertex_estimator.h) is exact where
// nothing is in the way, so the noise model can ask for few rays, but its O(1/n) bias where
// something is shows at 16 (tests/lighting/visibility_test.cpp).
inline constexpr int kMinAutoSamples = 32, kMaxAutoSamples = 1024, kAutoSampleStep = 16;
int chooseVisibilitySamples(const VisibilityNoiseModel& model, double budget,
                            int maxSamples = kMaxAutoSamples);

// The cap of auto rays follows the mesh: a coarse mesh averages few vertices under the kernel,
// so its B keeps more of E's noise and needs more rays per vertex, which it can afford. The cap
// spends at most kAutoRayBudget rays on the whole mesh (1024 rays on 16,384 vertices), never
// fewer than kMaxAutoSamples per vertex, nor more than kMaxAutoSamplesCoarse.
inline constexpr double kAutoRayBudget = 16384.0 * 1024.0;
inline constexpr int kMaxAutoSamplesCoarse = 16384;
int maxAutoSamples(std::size_t vertices);

}  // namespace sss
