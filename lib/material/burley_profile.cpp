#include "material/burley_profile.h"

#include <algorithm>
#include <cmath>

#include "material/beam_diffusion_profile.h"

namespace sss {

double burleyShapeFactor(double albedo) {
  return 1.9 - albedo + 3.5 * (albedo - 0.8) * (albedo - 0.8);
}

BurleyProfile::BurleyProfile(const glm::dvec3& albedo, const glm::dvec3& scalePerMm)
    : albedo_(albedo), s_(scalePerMm) {}

double burleyHalfEnergyScale() {
  // Solve e^{-x}/4 + 3/4 e^{-x/3} = 1/2 (decreasing in x) by bisection.
  static const double x = [] {
    double lo = 0.0, hi = 10.0;
    for (int i = 0; i < 80; ++i) {
      const double mid = 0.5 * (lo + hi);
      (0.25 * std::exp(-mid) + 0.75 * std::exp(-mid / 3.0) > 0.5 ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }();
  return x;
}

BurleyProfile::BurleyProfile(const Material& m) {
  // BeamDiffusionProfile validates the material.
  const BeamDiffusionProfile beam(m);
  albedo_ = beam.totalReflectance();
  const glm::dvec3 total = albedo_;
  for (int c = 0; c < 3; ++c) {
    // The beam's half-energy radius, by bisection on its disc integral.
    double lo = 0.0, hi = 1e-3;
    while (beam.integrateDisc(hi)[c] < 0.5 * total[c] && hi < 1e9) hi *= 2.0;
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      (beam.integrateDisc(mid)[c] < 0.5 * total[c] ? lo : hi) = mid;
    }
    s_[c] = burleyHalfEnergyScale() / (0.5 * (lo + hi));
  }
}

glm::dvec3 BurleyProfile::evaluate(double r) const {
  r = std::max(r, 1e-6);
  glm::dvec3 out;
  for (int c = 0; c < 3; ++c)
    out[c] =
        albedo_[c] * s_[c] * (std::exp(-s_[c] * r) + std::exp(-s_[c] * r / 3.0)) / (8.0 * M_PI * r);
  return out;
}

glm::dvec3 BurleyProfile::integrateDisc(double rho) const {
  glm::dvec3 out;
  for (int c = 0; c < 3; ++c)
    out[c] =
        albedo_[c] * (1.0 - 0.25 * std::exp(-s_[c] * rho) - 0.75 * std::exp(-s_[c] * rho / 3.0));
  return out;
}

}  // namespace sss
