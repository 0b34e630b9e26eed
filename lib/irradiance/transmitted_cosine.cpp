#include "irradiance/transmitted_cosine.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "optics/fresnel.h"

namespace sss {
namespace {

constexpr int kTableSize = 4097;

// Legendre polynomial P_l(x) by the three-term recurrence.
double legendre(int l, double x) {
  if (l == 0) return 1.0;
  double p0 = 1.0, p1 = x;
  for (int k = 2; k <= l; ++k) {
    const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
    p0 = p1;
    p1 = p2;
  }
  return p1;
}

}  // namespace

void checkSurfaceEta(float eta) {
  if (!(eta > 0.0f) || !std::isfinite(eta)) throw Error("eta must be a positive number");
}

TransmittedCosineKernel::TransmittedCosineKernel(float eta) : eta_(eta) {
  checkSurfaceEta(eta);
  if (isPlainCosine()) return;
  table_.resize(kTableSize);
  for (int i = 0; i < kTableSize; ++i) {
    table_[i] = fresnelTransmittance(static_cast<float>(i) / (kTableSize - 1), eta);
  }
}

float TransmittedCosineKernel::transmittance(float mu) const {
  if (table_.empty()) return 1.0f;
  const float f = std::clamp(mu, 0.0f, 1.0f) * (kTableSize - 1);
  const int i = std::min(static_cast<int>(f), kTableSize - 2);
  const float w = f - i;
  return (1.0f - w) * table_[i] + w * table_[i + 1];
}

double TransmittedCosineKernel::zonalCoefficient(int l) const {
  if (l < 0) return 0.0;
  if (isPlainCosine()) {
    // R&H Eq. 8-9 (Ramamoorthi & Hanrahan 2001).
    if (l == 0) return M_PI;
    if (l == 1) return 2.0 * M_PI / 3.0;
    if (l % 2 == 1) return 0.0;
    double ratio = 1.0;  // l! / (2^l ((l/2)!)^2)
    for (int k = 1; k <= l / 2; ++k) ratio *= (l / 2.0 + k) / (4.0 * k);
    const double sign = (l / 2) % 2 == 1 ? 1.0 : -1.0;
    return 2.0 * M_PI * sign / ((l + 2.0) * (l - 1.0)) * ratio;
  }
  return weightedZonalCoefficient(l, [](double) { return glm::dvec3(1.0); }).x;
}

// 2 pi int_0^1 mu F_t(mu) w(mu) P_l(mu) dmu, composite Simpson on the exact Fresnel term, with
// panels fine enough for the critical-angle kink of eta < 1, which lies inside a panel.
glm::dvec3 TransmittedCosineKernel::weightedZonalCoefficient(
    int l, const std::function<glm::dvec3(double mu)>& weight) const {
  if (l < 0) return glm::dvec3(0.0);
  const int panels = 8000;
  glm::dvec3 sum(0.0);
  for (int i = 0; i <= panels; ++i) {
    const double mu = static_cast<double>(i) / panels;
    const double w = (i == 0 || i == panels) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum +=
        w * mu * fresnelTransmittance(static_cast<float>(mu), eta_) * legendre(l, mu) * weight(mu);
  }
  return 2.0 * M_PI * sum / (3.0 * panels);
}

}  // namespace sss
