// Fresnel terms of a smooth dielectric boundary, shared by irradiance, bake, render and the Monte
// Carlo reference so that every tool uses one exit and entry model.
//
// Sources: the exact unpolarized Fresnel equations (Born & Wolf; pbrt-v4 FrDielectric);
// Schlick 1994 for the cheap form; the exit normalization of d'Eon 2012 ("A better dipole").
//
// The paper writes F_r for the factor that lets light *into* (and out of) the surface; that is
// the transmittance F_t = 1 - F_r, which is what the tools use.
#pragma once

#include <algorithm>
#include <cmath>

namespace sss {

// Reflectance of light arriving at cosThetaI (> 0: on the side the normal points to) at a
// boundary whose relative index is eta = n_transmitted / n_incident. eta < 1 may give total
// internal reflection (returns 1).
inline float fresnelDielectric(float cosThetaI, float eta) {
  cosThetaI = std::clamp(cosThetaI, 0.0f, 1.0f);
  const float sin2T = (1.0f - cosThetaI * cosThetaI) / (eta * eta);
  if (sin2T >= 1.0f) return 1.0f;
  const float cosT = std::sqrt(1.0f - sin2T);
  const float rPar = (eta * cosThetaI - cosT) / (eta * cosThetaI + cosT);
  const float rPerp = (cosThetaI - eta * cosT) / (cosThetaI + eta * cosT);
  return 0.5f * (rPar * rPar + rPerp * rPerp);
}

// Transmittance into a medium of relative index eta for light from outside at cosThetaI; by
// reciprocity also the factor for light leaving the medium towards outside direction cosThetaI.
inline float fresnelTransmittance(float cosThetaI, float eta) {
  return 1.0f - fresnelDielectric(cosThetaI, eta);
}

inline float fresnelSchlick(float cosThetaI, float eta) {
  const float r0 = (eta - 1.0f) * (eta - 1.0f) / ((eta + 1.0f) * (eta + 1.0f));
  const float m = 1.0f - std::clamp(cosThetaI, 0.0f, 1.0f);
  return r0 + (1.0f - r0) * m * m * m * m * m;
}

// Fresnel moment C_n(eta) = integral_0^1 F_r(mu, eta) mu^n dmu, by Gauss-Legendre-free
// composite Simpson quadrature (F_r has a kink only at the critical angle for eta < 1, which
// 2000 panels resolve).
inline double fresnelMoment(float eta, int n) {
  const int panels = 2000;
  const double h = 1.0 / panels;
  double sum = 0.0;
  for (int i = 0; i <= panels; ++i) {
    const double mu = i * h;
    const double w = (i == 0 || i == panels) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += w * fresnelDielectric(static_cast<float>(mu), eta) * std::pow(mu, n);
  }
  return sum * h / 3.0;
}

// Diffuse (cosine-weighted hemispherical) Fresnel reflectance: 2 C_1(eta).
inline double diffuseFresnelReflectance(float eta) {
  return 2.0 * fresnelMoment(eta, 1);
}

// Exit model: exitance B (W/m^2 leaving through the boundary) becomes radiance towards an
// outside direction with cosine mu_o as
//   L_o = B * F_t(mu_o, eta) / (pi * (1 - 2 C_1(eta))),
// the normalization making the emitted flux equal B (d'Eon 2012). exitRadianceScale returns
// 1 / (pi (1 - 2 C_1(eta))).
inline double exitRadianceScale(float eta) {
  return 1.0 / (M_PI * (1.0 - diffuseFresnelReflectance(eta)));
}

// The same along the normal (mu_o = 1): the radiance along the normal per unit B,
// F_t(1, eta) / (pi (1 - 2 C_1(eta))).
inline double normalExitRadianceScale(float eta) {
  return fresnelTransmittance(1.0f, eta) * exitRadianceScale(eta);
}

}  // namespace sss
