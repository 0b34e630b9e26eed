#include "material/windowed_profile.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace sss {

namespace {

constexpr int kDiscRings = 32;
constexpr int kTotalRings = 512;
constexpr double kTotalReachWindows = 7.0;  // W < 3e-11 beyond

}  // namespace

WindowedProfile::WindowedProfile(const DiffusionProfile& base, const glm::dvec3& windowMm)
    : base_(base), window_(windowMm) {
  for (int c = 0; c < 3; ++c)
    if (!(std::isfinite(windowMm[c]) && windowMm[c] > 0.0))
      fail("", "windowed profile: the window widths must be finite and positive");
  const double reach = kTotalReachWindows * std::max({window_.x, window_.y, window_.z});
  for (int k = 0; k < kTotalRings; ++k)
    total_ += ringIntegral(reach * k / kTotalRings, reach * (k + 1) / kTotalRings);
}

glm::dvec3 WindowedProfile::evaluate(double rMm) const {
  glm::dvec3 value = base_.evaluate(rMm);
  for (int c = 0; c < 3; ++c) value[c] *= std::exp(-0.5 * rMm * rMm / (window_[c] * window_[c]));
  return value;
}

glm::dvec3 WindowedProfile::ringIntegral(double rMm, double rNextMm) const {
  const glm::dvec3 ring = base_.integrateDisc(rNextMm) - base_.integrateDisc(rMm);
  const double mid = 0.5 * (rMm + rNextMm);
  glm::dvec3 out;
  for (int c = 0; c < 3; ++c)
    out[c] = ring[c] * std::exp(-0.5 * mid * mid / (window_[c] * window_[c]));
  return out;
}

glm::dvec3 WindowedProfile::integrateDisc(double rhoMm) const {
  glm::dvec3 sum(0.0);
  for (int k = 0; k < kDiscRings; ++k)
    sum += ringIntegral(rhoMm * k / kDiscRings, rhoMm * (k + 1) / kDiscRings);
  return sum;
}

}  // namespace sss
