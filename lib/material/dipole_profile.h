// Classic dipole diffusion profile.
//
// Source: Jensen, Marschner, Levoy, Hanrahan 2001, Eqs. 4-5:
//   R_d(r) = alpha'/(4 pi) [ z_r (1 + sigma_tr d_r) e^{-sigma_tr d_r} / d_r^3
//                          + z_v (1 + sigma_tr d_v) e^{-sigma_tr d_v} / d_v^3 ],
//   z_r = 1/sigma_t', z_v = z_r (1 + 4A/3), d_{r,v} = sqrt(r^2 + z_{r,v}^2),
//   sigma_tr = sqrt(3 sigma_a sigma_t'), A = (1 + F_dr) / (1 - F_dr).
// F_dr is the diffuse Fresnel reflectance seen from inside the medium, 2 C_1(1/eta), computed
// from the exact Fresnel equations (lib/optics/fresnel.h) instead of Jensen's polynomial fit
// (at eta = 1.3: 0.44445 exact vs 0.4446 fit, A = 2.600).
// Closed forms (integrating d/dd[-e^{-s d}/d] = (1 + s d) e^{-s d}/d^2):
//   total  = alpha'/2 (1 + e^{-4/3 A sqrt(3(1-alpha'))}) e^{-sqrt(3(1-alpha'))},
//   disc   = alpha'/2 sum_{z in z_r,z_v} (e^{-sigma_tr z} - z e^{-sigma_tr D}/D),
//            D = sqrt(rho^2 + z^2).
#pragma once

#include "material/diffusion_profile.h"

namespace sss {

// A = (1 + F_dr) / (1 - F_dr) with F_dr = 2 C_1(1/eta).
double dipoleBoundaryA(double eta);
// Total diffuse reflectance of the dipole for reduced albedo alphaPrime in [0, 1].
double dipoleTotalReflectance(double alphaPrime, double eta);
// Inverse of dipoleTotalReflectance in alpha' (bisection; monotonic). Throws sss::Error when
// reflectance is outside [0, dipoleTotalReflectance(1, eta)).
double dipoleAlbedoFromReflectance(double reflectance, double eta);

class DipoleProfile final : public DiffusionProfile {
 public:
  explicit DipoleProfile(const Material& material);
  std::string name() const override { return "dipole"; }
  glm::dvec3 evaluate(double rMm) const override;
  glm::dvec3 totalReflectance() const override;
  glm::dvec3 integrateDisc(double rhoMm) const override;

 private:
  glm::dvec3 alphaPrime_, sigmaTr_, zr_, zv_;
};

}  // namespace sss
