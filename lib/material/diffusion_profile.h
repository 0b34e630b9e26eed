// Radial diffusion profiles R_d(r): the diffuse reflectance at distance r (mm) from where unit
// flux enters a semi-infinite medium, per RGB channel, in mm^-2. The bake sums
// B(x_o) = sum_i R_d(|x_i - x_o|) E(x_i) A_i with E the Fresnel-transmitted irradiance.
//
// Models (one file each): DipoleProfile (Jensen et al. 2001), BeamDiffusionProfile (photon beam
// diffusion, Habel et al. 2013, tabulated), BurleyProfile (Christensen & Burley 2015 normalized
// diffusion). Every profile also has a sum-of-Gaussians fit (gaussian_sum_fit.h) for the fast
// bake methods.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "material/material.h"

namespace sss {

class DiffusionProfile {
 public:
  virtual ~DiffusionProfile() = default;

  // Short model name as accepted by makeProfile (profile_factory.h: "dipole", "beam", "burley").
  virtual std::string name() const = 0;
  // R_d(r) in mm^-2 for r >= 0 in mm; finite at r = 0 except where a model says otherwise
  // (Burley ~ 1/r: evaluate returns the value at a tiny r).
  virtual glm::dvec3 evaluate(double rMm) const = 0;
  // Total diffuse reflectance: integral_0^inf 2 pi r R_d(r) dr (closed form where one exists).
  virtual glm::dvec3 totalReflectance() const = 0;
  // Energy inside a disc: integral_0^rho 2 pi r R_d(r) dr. The bake's self term uses it so that
  // a vertex's own area integrates the profile instead of sampling its peak. Closed form for all
  // built-in models.
  virtual glm::dvec3 integrateDisc(double rhoMm) const = 0;

  // Smallest radius (mm) whose disc holds the fraction `fraction` (0..1) of the total in every
  // channel: the support the bake needs. Bisection on integrateDisc.
  double radiusContaining(double fraction) const;
};

// Reference quadrature of integral_a^b 2 pi r R_d(r) dr on log-spaced panels (Gauss-Legendre),
// for tests and for models without closed forms.
glm::dvec3 integrateProfileNumerically(const DiffusionProfile& profile, double aMm, double bMm);

}  // namespace sss
