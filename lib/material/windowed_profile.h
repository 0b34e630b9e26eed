// A profile's near field: R_d(r) W_c(r), W_c(r) = exp(-r^2 / (2 w_c^2)) per channel.
//
// Why: the bake's far field (lib/transport/far_field.h) traces the light that leaves far from where
// it entered with the weight 1 - W_c(d) of its exit distance d; the diffusion sum then spreads only
// the rest, with this profile, so that near and far add up to the whole transport without
// counting any of it twice. A Gaussian window keeps the product smooth (the sum-of-Gaussians fit
// of the fast methods still applies, gaussian_sum_fit.h) where a hard cut-off would ring.
//
// Parameters: the base profile (kept by reference) and the window widths w_c in mm (> 0).
#pragma once

#include <string>

#include <glm/vec3.hpp>

#include "material/diffusion_profile.h"

namespace sss {

class WindowedProfile final : public DiffusionProfile {
 public:
  // Throws Error unless every width is finite and positive.
  WindowedProfile(const DiffusionProfile& base, const glm::dvec3& windowMm);
  std::string name() const override { return base_.name() + "-near"; }
  glm::dvec3 evaluate(double rMm) const override;
  glm::dvec3 totalReflectance() const override { return total_; }
  // integral_0^rho 2 pi r R_d W dr from the base's closed-form disc integrals over 32 rings, W at
  // each ring's middle (W varies little over a vertex's disc, the only use: the self term).
  glm::dvec3 integrateDisc(double rhoMm) const override;

 private:
  glm::dvec3 ringIntegral(double rMm, double rNextMm) const;

  const DiffusionProfile& base_;
  glm::dvec3 window_;
  glm::dvec3 total_{0.0};
};

}  // namespace sss
