// How much of the light crossing the surface at an angle a half-space gives back, relative to
// diffuse light: one weight per channel, for light entering (a sun) and, by reciprocity, for the
// radiance leaving.
//
// Source: the half-space's directional albedo rho(mu) (material/halfspace_albedo.h; Monte Carlo
// per transmitted flux, tabulated over the reduced albedo a', eta and the outside cosine mu).
// Light arriving at grazing angles is refracted towards the critical angle, scatters shallower
// and comes back more than light at normal incidence, the more so the lower the albedo (skin1 at
// eta 1.3: w(0) / w(1) = 1.09 / 1.16 / 1.18 in R / G / B; marble 1.02-1.03). The diffusion profiles
// (Jensen et al. 2001; Christensen & Burley 2015) take every entering photon as diffuse, which
// holds under an even sky but not under a sun: the lit pole comes out too bright and the band
// near the terminator too dark (docs/physics.md, "Directional entry"). The directional dipole
// (Frisvad et al. 2014) models this inside the profile; here it is a weight, so every profile and
// diffusion method keeps working:
//   w_c(mu) = rho_c(mu) / R_c,   R_c = int_0^1 F_t(mu) rho_c(mu) mu dmu / int_0^1 F_t(mu) mu dmu.
// Entry: the irradiance the transport sums is E_w = int L F_t(mu) w(mu) mu dw; under uniform light
// E_w = E exactly (w averages to 1 over F_t mu), so every result under an even sky stands.
// Exit: by reciprocity the radiance a half-space sends at mu under uniform light is
// L(mu) = B F_t(mu) w(mu) / (pi (1 - 2 C_1)), the normalized exit model (d'Eon 2012) times w, so
// the emitted flux is still B (sss-render --exit-model calibrated).
// Parameters: the reduced scattering albedo a' per channel and the relative index eta.
#pragma once

#include <algorithm>
#include <array>

#include <glm/vec3.hpp>

namespace sss {

struct Material;  // material/material.h

class DirectionalAlbedoWeight {
 public:
  static constexpr int kNodes = 65;  // mu = k / 64; includes every table node (k / 16)

  // w = 1 at every angle (diffuse light).
  DirectionalAlbedoWeight();
  DirectionalAlbedoWeight(const glm::dvec3& reducedAlbedo, double eta);
  explicit DirectionalAlbedoWeight(const Material& material);

  // w_c at the outside direction cosine mu (clamped to [0, 1]); linear between the nodes, which
  // reproduces the table's own interpolation in mu. Inline: the visibility rays call it per ray.
  glm::vec3 at(float mu) const {
    const float t = std::clamp(mu, 0.0f, 1.0f) * (kNodes - 1);
    const int k = std::min(static_cast<int>(t), kNodes - 2);
    const float f = t - static_cast<float>(k);
    return weight_[k] + f * (weight_[k + 1] - weight_[k]);
  }
  const std::array<glm::vec3, kNodes>& nodes() const { return weight_; }

 private:
  std::array<glm::vec3, kNodes> weight_;
};

// Radiance leaving at the outside cosine mu per unit exitance under the calibrated exit model:
// F_t(mu, eta) w(mu) / (pi (1 - 2 C_1(eta))).
glm::vec3 calibratedExitRadiance(const DirectionalAlbedoWeight& weight, float mu, float eta);

}  // namespace sss
