// The radiance leaving a smooth dielectric boundary when the radiance inside, towards it, is
// linear in the internal cosine: L_i(mu_i) = c (1 + k mu_i), the P1 (diffusion) form of an interior
// radiance field (isotropic part plus a flux term; Ishimaru 1978, Jensen et al. 2001 Eq. 3).
//
// Why: the normalized exit model (fresnel.h, d'Eon 2012) takes the interior radiance as isotropic,
// k = 0. Light that has crossed a thin part after a few scatterings is not: an optically thin
// layer is brighter towards grazing directions inside (longer paths through it collect more
// scattering), k < 0, and an exit model with k = 0 puts 1.2x the true radiance along the normal on
// the unlit face of a 2 mm ketchup slab (docs/physics.md, "The far field's exit lobe"). The far
// field's light paths (transport/far_field.h) measure k per vertex from the mean internal cosine of
// their exits.
//
// With the exitance B (the flux that leaves per area) fixed, the radiance towards an outside
// direction of cosine mu_o is
//   L_o(mu_o) = B F_t(mu_o) (1 + k mu_i(mu_o)) / (pi (A_0 + k A_1)),
//   A_n = 2 int_0^1 F_t(mu_o) mu_i(mu_o)^n mu_o dmu_o,
// mu_i(mu_o) = sqrt(1 - (1 - mu_o^2) / eta^2) the cosine inside (Snell), F_t = 1 - F_r (exact
// Fresnel; F_t seen from inside at mu_i equals F_t from outside at mu_o by reciprocity). A_0 =
// 1 - 2 C_1(eta): k = 0 is the normalized exit model. The flux-weighted mean internal cosine of the
// light that leaves is m(k) = (A_1 + k A_2) / (A_0 + k A_1) (mu_o dmu_o = eta^2 mu_i dmu_i), which
// slopeFor inverts in closed form.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/vec3.hpp>

#include "core/noise_shrinkage.h"
#include "optics/fresnel.h"

namespace sss {

class ExitLobe {
 public:
  // k = -1 makes the interior radiance vanish along the normal; lower would make it negative.
  // Above kMaxSlope the lobe is within 1 % of its k -> infinity limit along the normal.
  static constexpr double kMinSlope = -1.0;
  static constexpr double kMaxSlope = 100.0;

  explicit ExitLobe(float eta) : eta_(eta) {
    // Composite Simpson in mu_o: F_t and mu_i are smooth for eta > 1 (no critical angle outside).
    constexpr int panels = 2000;
    const double h = 1.0 / panels;
    moments_.fill(0.0);
    for (int i = 0; i <= panels; ++i) {
      const double muO = i * h;
      const double w = (i == 0 || i == panels) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      const double ft = fresnelTransmittance(float(muO), eta);
      const double muI = internalCosine(float(muO), eta);
      for (int n = 0; n < 3; ++n) moments_[n] += w * ft * std::pow(muI, n) * muO;
    }
    for (double& m : moments_) m *= 2.0 * h / 3.0;
  }

  float eta() const { return eta_; }
  // A_n above, n = 0, 1, 2.
  double moment(int n) const { return moments_[n]; }

  // Cosine inside the medium of light that leaves at outside cosine muO.
  static float internalCosine(float muO, float eta) {
    const float c = std::clamp(muO, 0.0f, 1.0f);
    return std::sqrt(std::max(0.0f, 1.0f - (1.0f - c * c) / (eta * eta)));
  }

  // Radiance towards outside cosine muO per unit exitance, for slope k.
  double radiance(double slope, float muO) const {
    const double muI = internalCosine(muO, eta_);
    return fresnelTransmittance(muO, eta_) * (1.0 + slope * muI) /
           (M_PI * (moments_[0] + slope * moments_[1]));
  }

  // radiance(k, 1) per channel: the radiance along the normal per unit exitance for slopes k.
  glm::dvec3 normalRadiance(const glm::vec3& slopes) const {
    return {radiance(slopes.x, 1.0f), radiance(slopes.y, 1.0f), radiance(slopes.z, 1.0f)};
  }

  // The slope whose radiance along the normal is `ratio` times the normalized model's:
  // (1 + k) A_0 / (A_0 + k A_1) = ratio, k = A_0 (ratio - 1) / (A_0 - ratio A_1), clamped to
  // [kMinSlope, kMaxSlope].
  double slopeForNormalRatio(double ratio) const {
    const double a0 = moments_[0], a1 = moments_[1], d = a0 - ratio * a1;
    if (!(d > 0.0)) return kMaxSlope;
    return std::clamp(a0 * (ratio - 1.0) / d, kMinSlope, kMaxSlope);
  }

  // The flux-weighted mean internal cosine of the light that leaves, for slope k.
  double meanCosine(double slope) const {
    return (moments_[1] + slope * moments_[2]) / (moments_[0] + slope * moments_[1]);
  }

  // The slope whose mean internal cosine is `meanCosine`, clamped to [kMinSlope, kMaxSlope]
  // (a measured mean outside what the family reaches takes the nearest end).
  double slopeFor(double meanCosine) const {
    const double lo = this->meanCosine(kMinSlope), hi = this->meanCosine(kMaxSlope);
    if (!(meanCosine > lo)) return kMinSlope;
    if (!(meanCosine < hi)) return kMaxSlope;
    return (moments_[1] - meanCosine * moments_[0]) / (meanCosine * moments_[1] - moments_[2]);
  }

  // The slope for a measured mean cosine whose variance (its noise) is `variance`, shrunk towards 0
  // (the normalized exit model) by its own noise: k k^2 / (k^2 + var k), var k = (dk/dm)^2 var m
  // (a Wiener-like weight: a slope well above its noise stays, one within it fades). Where the
  // lobe is not resolved, a noisy slope would add more error than the lobe removes, since the
  // slope amplifies the mean cosine's noise.
  double shrunkSlopeFor(double meanCosine, double variance) const {
    const double dk = slopeDerivative(meanCosine);
    return shrunkByNoise(slopeFor(meanCosine), dk * dk * std::max(0.0, variance));
  }

  // d slopeFor / d meanCosine inside the clamps: (A_0 A_2 - A_1^2) / (m A_1 - A_2)^2 (> 0), so
  // that a mean cosine's noise gives the slope's.
  double slopeDerivative(double meanCosine) const {
    const double d = meanCosine * moments_[1] - moments_[2];
    return (moments_[0] * moments_[2] - moments_[1] * moments_[1]) / (d * d);
  }

 private:
  float eta_;
  std::array<double, 3> moments_{};
};

}  // namespace sss
