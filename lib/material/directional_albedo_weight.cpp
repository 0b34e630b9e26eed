#include "material/directional_albedo_weight.h"

#include <algorithm>

#include "material/halfspace_albedo.h"
#include "material/material.h"
#include "optics/fresnel.h"

namespace sss {

DirectionalAlbedoWeight::DirectionalAlbedoWeight() {
  weight_.fill(glm::vec3(1.0f));
}

DirectionalAlbedoWeight::DirectionalAlbedoWeight(const Material& material)
    : DirectionalAlbedoWeight(material.reducedAlbedo(), material.eta) {}

DirectionalAlbedoWeight::DirectionalAlbedoWeight(const glm::dvec3& reducedAlbedo, double eta) {
  // R_c by the midpoint rule on a fine grid of the same interpolated table, so that w averages
  // to 1 over F_t mu up to the quadrature (< 1e-4).
  constexpr int kQuadrature = 1024;
  glm::dvec3 average(0.0);
  double norm = 0.0;
  for (int i = 0; i < kQuadrature; ++i) {
    const double mu = (i + 0.5) / kQuadrature;
    const double ft = fresnelTransmittance(static_cast<float>(mu), static_cast<float>(eta)) * mu;
    for (int c = 0; c < 3; ++c)
      average[c] += ft * halfSpaceDirectionalAlbedo(reducedAlbedo[c], eta, mu);
    norm += ft;
  }
  average /= norm;
  for (int k = 0; k < kNodes; ++k) {
    const double mu = static_cast<double>(k) / (kNodes - 1);
    for (int c = 0; c < 3; ++c)
      weight_[k][c] = average[c] > 1e-6
                          ? static_cast<float>(
                                halfSpaceDirectionalAlbedo(reducedAlbedo[c], eta, mu) / average[c])
                          : 1.0f;  // nothing comes back: any weight is the same
  }
}

glm::vec3 calibratedExitRadiance(const DirectionalAlbedoWeight& weight, float mu, float eta) {
  return weight.at(mu) * static_cast<float>(fresnelTransmittance(mu, eta) * exitRadianceScale(eta));
}

}  // namespace sss
