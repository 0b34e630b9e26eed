// The irradiance kernel of a smooth dielectric surface:
//   k(mu) = F_t(mu, eta) * max(mu, 0),   F_t = 1 - F_r (exact dielectric Fresnel, optics/fresnel.h)
// so that E_t(n) = integral of k(n . w) L(w) dw is the Fresnel-transmitted irradiance of
// Li & Guo Eq. 6 (they write F_r for what lets light in; that is the transmittance). With
// eta = 1, F_t = 1 and k is the clamped cosine of Li & Guo Eq. 12: plain irradiance.
//
// Zonal (Funk-Hecke) coefficients, Ramamoorthi & Hanrahan 2001 ("An efficient representation for
// irradiance environment maps"), R&H Eq. 7-9: integral of k(n . w) Y_lm(w) dw = kHat_l Y_lm(n) with
//   kHat_l = 2 pi integral_{-1}^{1} k(mu) P_l(mu) dmu;  eta = 1: pi, 2 pi / 3, pi / 4, 0, -pi / 24.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

namespace sss {

// Throws Error unless eta, the surface's relative index, is a positive finite number (eta < 1:
// light entering a less dense medium, with total internal reflection past the critical angle):
// the kernel's domain. The tools' --eta is the material's, checked by checkMaterialEta
// (lib/material/material.h, [1, 3]) in every tool alike.
void checkSurfaceEta(float eta);

class TransmittedCosineKernel {
 public:
  explicit TransmittedCosineKernel(float eta = 1.0f);  // checkSurfaceEta(eta)

  float eta() const { return eta_; }
  bool isPlainCosine() const { return eta_ == 1.0f; }
  // F_t(mu, eta) for mu in [0, 1], interpolated linearly in a table (tests/irradiance bound its
  // error); exactly 1 when eta = 1.
  float transmittance(float mu) const;
  // k(mu); 0 for mu <= 0.
  float operator()(float mu) const { return mu > 0.0f ? mu * transmittance(mu) : 0.0f; }
  // kHat_l (above), by quadrature; exact closed forms when eta = 1.
  double zonalCoefficient(int l) const;
  // The same for the kernel times a per-channel weight of the cosine, k(mu) w(mu) (the directional
  // entry, material/directional_albedo_weight.h): 2 pi integral_0^1 k(mu) w(mu) P_l(mu) dmu, by
  // the same quadrature.
  glm::dvec3 weightedZonalCoefficient(int l,
                                      const std::function<glm::dvec3(double mu)>& weight) const;

 private:
  float eta_;
  std::vector<float> table_;  // F_t at mu = i / (size - 1)
};

}  // namespace sss
