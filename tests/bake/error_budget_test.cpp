// The error budget (lib/bake/error_budget.h): the shares of the tolerance each estimate gets, the
// diffusion sum's tolerance from what the others left (the closed form of error_budget.h),
// and the total of independent errors in quadrature.
#include "bake/error_budget.h"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>

namespace sss {
namespace {

constexpr double kTolerance = 0.02;
constexpr double kEps = 1e-15;

// The shares are the documented constants times the tolerance: 60 % for the walks, 90 % for the
// rays alone and 70 % beside the walks, 30 % for the unscattered light (error_budget.h).
TEST(ErrorBudget, BudgetsAreTheDocumentedSharesOfTheTolerance) {
  const ErrorBudget budget(kTolerance);
  EXPECT_EQ(budget.tolerance(), kTolerance);
  EXPECT_NEAR(budget.walkBudget(), 0.6 * kTolerance, kEps);
  EXPECT_NEAR(budget.visibilityBudget(false), 0.9 * kTolerance, kEps);
  EXPECT_NEAR(budget.visibilityBudget(true), 0.7 * kTolerance, kEps);
  EXPECT_NEAR(budget.unscatteredBudget(), 0.3 * kTolerance, kEps);
  EXPECT_EQ(budget.visibilityShare(false), 0.9);
  EXPECT_EQ(budget.visibilityShare(true), 0.7);
  // Beside the walks the rays' share shrinks so that the two fit the tolerance together:
  // 0.6^2 + 0.7^2 = 0.85 < 1, while 0.6^2 + 0.9^2 would not.
  EXPECT_LT(std::hypot(ErrorBudget::kWalkShare, ErrorBudget::kVisibilityShareWithWalks), 1.0);
  EXPECT_GT(std::hypot(ErrorBudget::kWalkShare, ErrorBudget::kVisibilityShare), 1.0);
}

// With no other estimate run (no escape walks, no budgeted rays) nothing is spent: the floor
// sqrt(1 - 0) tol and the rest sqrt(tol^2 - 0) are both the whole tolerance. A walk error without
// escape walks has share 0, so the floor is still the whole tolerance.
TEST(ErrorBudget, NothingSpentLeavesTheWholeToleranceToTheDiffusionSum) {
  const ErrorBudget budget(kTolerance);
  EXPECT_NEAR(budget.diffusionTolerance(false, 0.0, std::nullopt), kTolerance, kEps);
  EXPECT_NEAR(budget.diffusionTolerance(false, 0.5 * kTolerance, std::nullopt), kTolerance, kEps);
  // Budgeted rays that left no noise (a convex object) spend nothing either.
  EXPECT_NEAR(budget.diffusionTolerance(false, 0.0, 0.0), kTolerance, kEps);
  EXPECT_NEAR(budget.diffusionTolerance(true, 0.0, 0.0), kTolerance, kEps);
}

// Errors within their shares: the diffusion sum gets the rest in quadrature,
// sqrt(tol^2 - e_walks^2 - e_visibility^2), so that the three errors add up to the tolerance
// exactly (hypot of the three = tol).
TEST(ErrorBudget, SpentErrorsLeaveTheRestInQuadrature) {
  const ErrorBudget budget(kTolerance);
  // Walks alone: 0.3 tol spent leaves sqrt(1 - 0.09) tol (above the floor sqrt(1 - 0.36) tol).
  const double walks = 0.3 * kTolerance;
  const double afterWalks = budget.diffusionTolerance(true, walks, std::nullopt);
  EXPECT_NEAR(afterWalks, std::sqrt(1.0 - 0.09) * kTolerance, 1e-12);
  EXPECT_NEAR(std::hypot(afterWalks, walks), kTolerance, 1e-12);
  // Rays alone: 0.5 tol leaves sqrt(1 - 0.25) tol (floor sqrt(1 - 0.81) tol).
  const double rays = 0.5 * kTolerance;
  const double afterRays = budget.diffusionTolerance(false, 0.0, rays);
  EXPECT_NEAR(afterRays, std::sqrt(0.75) * kTolerance, 1e-12);
  EXPECT_NEAR(std::hypot(afterRays, rays), kTolerance, 1e-12);
  // Both: 0.3 and 0.4 tol leave sqrt(1 - 0.09 - 0.16) tol (floor sqrt(1 - 0.36 - 0.49) tol).
  const double rays2 = 0.4 * kTolerance;
  const double afterBoth = budget.diffusionTolerance(true, walks, rays2);
  EXPECT_NEAR(afterBoth, std::sqrt(0.75) * kTolerance, 1e-12);
  EXPECT_NEAR(ErrorBudget::total(rays2, afterBoth, walks), kTolerance, 1e-12);
}

// Errors beyond their shares (the walks capped, the rays capped): the rest in quadrature would be
// small or nothing (sqrt(max(0, ...))), and the diffusion sum keeps the floor its shares leave,
// sqrt(1 - sum s_k^2) tol: 0.8 tol after the walks (share 0.6), sqrt(0.19) tol after the rays
// alone (share 0.9), sqrt(0.15) tol after both (shares 0.6 and 0.7).
TEST(ErrorBudget, EstimatesOverTheirSharesLeaveTheFloorOfTheShares) {
  const ErrorBudget budget(kTolerance);
  EXPECT_NEAR(budget.diffusionTolerance(true, 2.0 * kTolerance, std::nullopt), 0.8 * kTolerance,
              1e-12);
  EXPECT_NEAR(budget.diffusionTolerance(false, 0.0, 1.5 * kTolerance),
              std::sqrt(1.0 - 0.81) * kTolerance, 1e-12);
  EXPECT_NEAR(budget.diffusionTolerance(true, 0.9 * kTolerance, 0.9 * kTolerance),
              std::sqrt(1.0 - 0.36 - 0.49) * kTolerance, 1e-12);
  // Just over the crossing: spending e_walks = 0.6 tol leaves exactly the floor 0.8 tol, and
  // more walk error than that leaves the floor, not less.
  EXPECT_NEAR(budget.diffusionTolerance(true, 0.6 * kTolerance, std::nullopt), 0.8 * kTolerance,
              1e-12);
  EXPECT_NEAR(budget.diffusionTolerance(true, 0.61 * kTolerance, std::nullopt), 0.8 * kTolerance,
              1e-12);
}

// The diffusion sum's tolerance never grows as the others spend more (a monotone split), and it
// scales with the tolerance (every term is linear in tol and the errors).
TEST(ErrorBudget, DiffusionToleranceFallsWithSpentErrorAndScalesWithTheTolerance) {
  const ErrorBudget budget(kTolerance), doubled(2.0 * kTolerance);
  double previous = budget.diffusionTolerance(true, 0.0, 0.0);
  for (int k = 1; k <= 40; ++k) {
    const double e = 0.025 * k * kTolerance;
    const double t = budget.diffusionTolerance(true, e, e);
    EXPECT_LE(t, previous + 1e-15) << "spent " << e;
    previous = t;
    EXPECT_NEAR(doubled.diffusionTolerance(true, 2.0 * e, 2.0 * e), 2.0 * t, 1e-12);
  }
}

// Without escape walks no walk error is spent, so a stray walk error leaves the rays' split as it
// is: with the rays at 0.005 of a 0.01 tolerance, sqrt(0.01^2 - 0.005^2) whatever walkError says.
TEST(ErrorBudget, WalkErrorCountsOnlyWithEscapeWalks) {
  const ErrorBudget budget(0.01);
  const double expected = std::sqrt(0.01 * 0.01 - 0.005 * 0.005);
  EXPECT_NEAR(budget.diffusionTolerance(false, 0.006, 0.005), expected, 1e-15);
  EXPECT_NEAR(budget.diffusionTolerance(false, 0.0, 0.005), expected, 1e-15);
  EXPECT_LT(budget.diffusionTolerance(true, 0.006, 0.005), expected);
}

// Independent errors add in quadrature: total = sqrt(a^2 + b^2 + c^2) (3-4-12-13 is exact).
TEST(ErrorBudget, TotalAddsIndependentErrorsInQuadrature) {
  EXPECT_NEAR(ErrorBudget::total(3.0, 4.0, 12.0), 13.0, 1e-12);
  EXPECT_NEAR(ErrorBudget::total(0.0, 0.01, 0.0), 0.01, 1e-15);
  EXPECT_NEAR(ErrorBudget::total(0.006, 0.0, 0.008), 0.01, 1e-15);
  EXPECT_EQ(ErrorBudget::total(0.0, 0.0, 0.0), 0.0);
  // Symmetric in its arguments (to rounding), and sqrt(30) 1e-3 here.
  EXPECT_DOUBLE_EQ(ErrorBudget::total(1e-3, 2e-3, 5e-3), ErrorBudget::total(5e-3, 1e-3, 2e-3));
  EXPECT_DOUBLE_EQ(ErrorBudget::total(1e-3, 2e-3, 5e-3), std::sqrt(30.0) * 1e-3);
}

}  // namespace
}  // namespace sss
