#include "material/diffusion_profile.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace sss {

double DiffusionProfile::radiusContaining(double fraction) const {
  const glm::dvec3 total = totalReflectance();
  auto enough = [&](double rho) {
    const glm::dvec3 inside = integrateDisc(rho);
    for (int c = 0; c < 3; ++c)
      if (total[c] > 0.0 && inside[c] < fraction * total[c]) return false;
    return true;
  };
  double hi = 1e-3;
  while (!enough(hi) && hi < 1e9) hi *= 2.0;
  double lo = 0.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (enough(mid) ? hi : lo) = mid;
  }
  return hi;
}

glm::dvec3 integrateProfileNumerically(const DiffusionProfile& profile, double a, double b) {
  // 8-point Gauss-Legendre on panels equally spaced in ln r (from a tiny inner radius when
  // a = 0: the integrand 2 pi r R_d is bounded there, so [0, 1e-9] contributes nothing).
  static const double x[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                              -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                              0.7966664774136267,  0.9602898564975363};
  static const double w[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                              0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                              0.2223810344533745, 0.1012285362903763};
  const double la = std::log(std::max(a, 1e-9)), lb = std::log(b);
  const int panels = std::max(1, static_cast<int>(std::ceil((lb - la) * 16.0)));
  const double h = (lb - la) / panels;
  glm::dvec3 sum(0.0);
  for (int p = 0; p < panels; ++p) {
    const double mid = la + (p + 0.5) * h;
    for (int i = 0; i < 8; ++i) {
      const double r = std::exp(mid + 0.5 * h * x[i]);
      // dr = r d(ln r)
      sum += (w[i] * 0.5 * h * 2.0 * M_PI * r * r) * profile.evaluate(r);
    }
  }
  return sum;
}

}  // namespace sss
