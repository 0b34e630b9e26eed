// A single normalized 2D Gaussian as a profile:
//   G(v, r) = e^{-r^2 / 2v} / (2 pi v),  total 1,  disc 1 - e^{-rho^2 / 2v},
// the same variance v (mm^2) in every channel. Not a diffusion model: the wide kernel over which
// the escape energy model (lib/transport/finite_object_energy.h) spreads the light that a finite
// object returns beyond a half-space's albedo. As a DiffusionProfile it runs through every method
// of lib/diffusion/diffusion.h (its fit is one Gaussian).
#pragma once

#include "material/diffusion_profile.h"

namespace sss {

class GaussianProfile final : public DiffusionProfile {
 public:
  explicit GaussianProfile(double varianceMm2);  // throws Error unless finite and > 0
  std::string name() const override { return "gaussian"; }
  glm::dvec3 evaluate(double rMm) const override;
  glm::dvec3 totalReflectance() const override { return glm::dvec3(1.0); }
  glm::dvec3 integrateDisc(double rhoMm) const override;

 private:
  double variance_;
};

}  // namespace sss
