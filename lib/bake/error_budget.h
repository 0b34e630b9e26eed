// How a bake's tolerance (the relative RMS error of B it may leave) is split between its
// independent estimates: the escape walks (finite_object_energy.h), the visibility rays
// (visibility.h, with "auto" samples) and the diffusion sum (diffusion.h). The errors are
// independent, so they add in quadrature:
//
//   total = sqrt(e_visibility^2 + e_diffusion^2 + e_walks^2) <= tolerance.
//
// The walks and the rays get fixed shares of the tolerance as their budgets (rays are the
// expensive part, so they get the larger share; a walk buys less error than a ray, so with the
// escape model the rays' share shrinks to leave room for the walks). The diffusion sum then gets
// what the others actually left, but never less than what their shares leave:
//
//   tol_diffusion = max(sqrt(1 - sum_k s_k^2) tol, sqrt(max(0, tol^2 - sum_k e_k^2)))
//
// over the estimates k that ran (s_k their shares, e_k their predicted errors).
#pragma once

#include <optional>

namespace sss {

class ErrorBudget {
 public:
  explicit ErrorBudget(double tolerance) : tolerance_(tolerance) {}
  double tolerance() const { return tolerance_; }

  // Share of the tolerance the escape walks' noise may take (asked before the energy model is
  // decided, so the same whether or not escape is chosen).
  static constexpr double kWalkShare = 0.6;
  // Share the visibility rays may take with auto samples: alone, and beside the escape walks.
  static constexpr double kVisibilityShare = 0.9;
  static constexpr double kVisibilityShareWithWalks = 0.7;

  double walkBudget() const { return kWalkShare * tolerance_; }
  double visibilityShare(bool escapeWalks) const {
    return escapeWalks ? kVisibilityShareWithWalks : kVisibilityShare;
  }
  // The unscattered light's noise budget (unscattered_light.h), outside the split: it is light the
  // other estimates leave out, added to the radiance along the normal, not an error of B.
  static constexpr double kUnscatteredShare = 0.3;
  double unscatteredBudget() const { return kUnscatteredShare * tolerance_; }

  double visibilityBudget(bool escapeWalks) const {
    return visibilityShare(escapeWalks) * tolerance_;
  }

  // The diffusion sum's tolerance after the escape walks (walkError, when escapeWalks) and, when
  // the rays were budgeted (auto samples), the visibility noise (visibilityError).
  double diffusionTolerance(bool escapeWalks, double walkError,
                            std::optional<double> visibilityError) const;

  // The predicted total of independent errors.
  static double total(double visibility, double diffusion, double walks);

 private:
  double tolerance_;
};

}  // namespace sss
