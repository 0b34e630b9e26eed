// An independent reference for the light tracer's tests: Monte Carlo of a plane-parallel (1D)
// slab under a collimated beam. Only the depth z and the direction cosine mu are tracked (the
// lateral position does not matter in an infinite slab), so nothing of lib/pathtrace is used:
// photons enter with the Fresnel transmittance, fly exponential distances, scatter with albedo
// weighting (isotropic or Henyey-Greenstein, the new cosine by the spherical cosine rule) and at
// either face reflect with the exact Fresnel reflectance (total internal reflection included) or
// leave. Unscattered light is counted.
#pragma once

#include <cmath>
#include <cstdint>

#include "core/random.h"
#include "core/sampling.h"
#include "optics/fresnel.h"

namespace sss::test {

struct SlabFractions {
  double reflected = 0.0;    // diffuse: entered, then left through the lit face
  double transmitted = 0.0;  // left through the far face
  double specular = 0.0;     // reflected at the lit face without entering
};

// Fractions of a collimated beam's power at incidence cosine mu0 (outside) on a slab of
// thickness d (mm) with coefficients sigmaS, sigmaA (mm^-1), relative index eta, HG mean cosine g.
inline SlabFractions planeParallelSlab(double d, double sigmaS, double sigmaA, double eta, double g,
                                       double mu0, uint64_t photons, uint64_t seed) {
  SlabFractions out;
  const double sigmaT = sigmaS + sigmaA, albedo = sigmaS / sigmaT;
  const float feta = float(eta);
  const double fr0 = fresnelDielectric(float(mu0), feta);
  out.specular = fr0;
  const double muIn = std::sqrt(1.0 - (1.0 - mu0 * mu0) / (eta * eta));
  for (uint64_t i = 0; i < photons; ++i) {
    Pcg32 rng(seed, i);
    double w = 1.0 - fr0, z = 0.0, mu = muIn;  // z down from the lit face, mu = cos to +z
    for (int step = 0; step < 100000 && w > 1e-12; ++step) {
      const double s = -std::log(1.0 - rng.uniformDouble()) / sigmaT;
      const double zNext = z + s * mu;
      if (zNext <= 0.0 || zNext >= d) {
        z = zNext <= 0.0 ? 0.0 : d;
        if (rng.uniformDouble() < fresnelDielectric(float(std::abs(mu)), 1.0f / feta)) {
          mu = -mu;
          continue;
        }
        (z == 0.0 ? out.reflected : out.transmitted) += w;
        break;
      }
      z = zNext;
      w *= albedo;
      const double cosTheta = sampleHenyeyGreensteinCosine(g, rng.uniformDouble());
      const double sinTheta = std::sqrt(std::max(0.0, 1.0 - cosTheta * cosTheta));
      const double phi = 2.0 * M_PI * rng.uniformDouble();
      mu = mu * cosTheta + std::sqrt(std::max(0.0, 1.0 - mu * mu)) * sinTheta * std::cos(phi);
    }
  }
  out.reflected /= double(photons);
  out.transmitted /= double(photons);
  return out;
}

}  // namespace sss::test
