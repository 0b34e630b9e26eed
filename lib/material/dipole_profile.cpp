#include "material/dipole_profile.h"

#include <cmath>
#include <sstream>

#include "core/error.h"
#include "optics/fresnel.h"

namespace sss {

double dipoleBoundaryA(double eta) {
  // Light inside hits the boundary towards a medium of relative index 1/eta.
  const double fdr = diffuseFresnelReflectance(static_cast<float>(1.0 / eta));
  return (1.0 + fdr) / (1.0 - fdr);
}

namespace {
double totalForA(double alphaPrime, double A) {
  const double s = std::sqrt(3.0 * (1.0 - alphaPrime));
  return 0.5 * alphaPrime * (1.0 + std::exp(-4.0 / 3.0 * A * s)) * std::exp(-s);
}
}  // namespace

double dipoleTotalReflectance(double alphaPrime, double eta) {
  return totalForA(alphaPrime, dipoleBoundaryA(eta));
}

double dipoleAlbedoFromReflectance(double reflectance, double eta) {
  const double A = dipoleBoundaryA(eta);
  const double maxR = totalForA(1.0, A);
  if (!(reflectance >= 0.0 && reflectance < maxR)) {
    std::ostringstream out;
    out << "diffuse reflectance " << reflectance << " is outside [0, " << maxR << ")";
    fail("", out.str());
  }
  // totalForA is increasing in alpha'; bisection to double precision.
  double lo = 0.0, hi = 1.0;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (totalForA(mid, A) < reflectance ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

DipoleProfile::DipoleProfile(const Material& m) {
  validateMaterial(m, m.name.empty() ? "material" : m.name);
  const double A = dipoleBoundaryA(m.eta);
  alphaPrime_ = m.reducedAlbedo();
  sigmaTr_ = m.sigmaTr();
  zr_ = 1.0 / m.sigmaTPrime();
  zv_ = zr_ * (1.0 + 4.0 / 3.0 * A);
}

glm::dvec3 DipoleProfile::evaluate(double r) const {
  glm::dvec3 out;
  const double r2 = r * r;
  for (int c = 0; c < 3; ++c) {
    const double s = sigmaTr_[c];
    const double dr = std::sqrt(r2 + zr_[c] * zr_[c]);
    const double dv = std::sqrt(r2 + zv_[c] * zv_[c]);
    const double real = zr_[c] * (1.0 + s * dr) * std::exp(-s * dr) / (dr * dr * dr);
    const double virt = zv_[c] * (1.0 + s * dv) * std::exp(-s * dv) / (dv * dv * dv);
    out[c] = alphaPrime_[c] / (4.0 * M_PI) * (real + virt);
  }
  return out;
}

glm::dvec3 DipoleProfile::totalReflectance() const {
  glm::dvec3 out;
  for (int c = 0; c < 3; ++c)
    out[c] =
        0.5 * alphaPrime_[c] * (std::exp(-sigmaTr_[c] * zr_[c]) + std::exp(-sigmaTr_[c] * zv_[c]));
  return out;
}

glm::dvec3 DipoleProfile::integrateDisc(double rho) const {
  glm::dvec3 out;
  for (int c = 0; c < 3; ++c) {
    double sum = 0.0;
    for (double z : {zr_[c], zv_[c]}) {
      const double D = std::sqrt(rho * rho + z * z);
      sum += std::exp(-sigmaTr_[c] * z) - z * std::exp(-sigmaTr_[c] * D) / D;
    }
    out[c] = 0.5 * alphaPrime_[c] * sum;
  }
  return out;
}

}  // namespace sss
