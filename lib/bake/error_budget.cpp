#include "bake/error_budget.h"

#include <algorithm>
#include <cmath>

namespace sss {

namespace {

// max(sqrt(1 - s1^2 - s2^2) tol, sqrt(max(0, tol^2 - e1^2 - e2^2))): the formula of
// error_budget.h for up to two other estimates (a share and an error of 0 for one that did not
// run).
double leftOver(double tolerance, double s1, double e1, double s2, double e2) {
  return std::max(std::sqrt(1.0 - s1 * s1 - s2 * s2) * tolerance,
                  std::sqrt(std::max(0.0, tolerance * tolerance - e1 * e1 - e2 * e2)));
}

}  // namespace

double ErrorBudget::diffusionTolerance(bool escapeWalks, double walkError,
                                       std::optional<double> visibilityError) const {
  // Without escape walks there is no walk error to leave room for, whatever the caller passes.
  const double walkShare = escapeWalks ? kWalkShare : 0.0;
  const double walks = escapeWalks ? walkError : 0.0;
  if (!visibilityError) return leftOver(tolerance_, walkShare, walks, 0.0, 0.0);
  return leftOver(tolerance_, visibilityShare(escapeWalks), *visibilityError, walkShare, walks);
}

double ErrorBudget::total(double visibility, double diffusion, double walks) {
  return std::hypot(visibility, diffusion, walks);
}

}  // namespace sss
