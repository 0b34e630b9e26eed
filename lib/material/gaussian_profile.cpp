#include "material/gaussian_profile.h"

#include <cmath>

#include "core/error.h"
#include "material/gaussian_sum_fit.h"

namespace sss {

GaussianProfile::GaussianProfile(double varianceMm2) : variance_(varianceMm2) {
  if (!(std::isfinite(varianceMm2) && varianceMm2 > 0.0))
    fail("", "Gaussian profile: the variance must be finite and positive");
}

glm::dvec3 GaussianProfile::evaluate(double rMm) const {
  return glm::dvec3(normalizedGaussian(variance_, rMm));
}

glm::dvec3 GaussianProfile::integrateDisc(double rhoMm) const {
  return glm::dvec3(gaussianDiscIntegral(variance_, rhoMm));
}

}  // namespace sss
