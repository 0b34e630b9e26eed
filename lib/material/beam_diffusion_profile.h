// Photon beam diffusion (PBD) profile shape, energy-calibrated to transport truth, tabulated.
//
// Shape: Habel, Christensen, Jarosz, "Photon Beam Diffusion: A Hybrid Monte Carlo Method for
// Subsurface Scattering", EGSR 2013, with the boundary of d'Eon 2012 ("A better dipole"); the
// quadrature follows pbrt-v3 Sec. 15.5 (BeamDiffusionMS/SS). The incident beam is refracted
// straight down; sources along it at depth t with density sigma_t' e^{-sigma_t' t}, each a
// dipole with the better-dipole boundary:
//   D = (2 sigma_a + sigma_s') / (3 sigma_t'^2), sigma_tr = sqrt(sigma_a / D),
//   z_e = 2 D (1 + 3 C_2) / (1 - 2 C_1), z_v = -t - 2 z_e, C_n = C_n(1/eta) (inside),
//   R_ms(r) = int alpha'^2 kappa(t) [C_phi phi(r,t) + C_E E(r,t)] dt,
//   C_phi = (1 - 2 C_1)/4, C_E = (1 - 3 C_2)/2, kappa = 1 - e^{-2 sigma_t' (d_r + t)},
// plus the exact single-scattering term R_ss of a normally incident beam (isotropic phase,
// Fresnel-transmitted exit). Reduced coefficients are used throughout (similarity, g -> 0).
// Energy: PBD's total is off (index-matched, normal incidence, against Chandrasekhar's
// H-function: its single-scattering part is exact, the diffusion part too high), and the bake
// lights with diffuse irradiance anyway. So each channel is scaled to
// halfSpaceDiffuseAlbedo(alpha', eta) (halfspace_albedo.h): the Monte Carlo half-space albedo
// under diffuse light with the Fresnel boundary. totalReflectance() is that value. How far the
// classic dipole's totals are from it: tests/bench/results/material/totals.csv and
// docs/physics.md, "Where we correct the paper".
// Tabulated per channel on 160 log-spaced radii from 1e-4 mean free paths to
// max(min(64 / sigma_tr, 1e4 / sigma_t'), 40 / sigma_t'), 256 depth samples each, interpolated
// log-log; the tail beyond the table is dropped. integrateDisc integrates the log-log
// interpolant exactly.
#pragma once

#include <vector>

#include "material/diffusion_profile.h"

namespace sss {

class BeamDiffusionProfile final : public DiffusionProfile {
 public:
  explicit BeamDiffusionProfile(const Material& material);
  std::string name() const override { return "beam"; }
  glm::dvec3 evaluate(double rMm) const override;
  glm::dvec3 totalReflectance() const override { return total_; }
  glm::dvec3 integrateDisc(double rhoMm) const override;

 private:
  struct Channel {
    std::vector<double> r, value, cumulative;  // cumulative: disc integral up to r[i]
  };
  Channel channels_[3];
  glm::dvec3 total_{0.0};
};

}  // namespace sss
