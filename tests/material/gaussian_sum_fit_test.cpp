// Sum-of-Gaussians: the normalized Gaussian (composition, disc integral), and the fit's promise
// (fewest Gaussians within tolerance, energy preserved) for every preset and profile.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "material/diffusion_profile.h"
#include "material/gaussian_profile.h"
#include "material/gaussian_sum_fit.h"
#include "material/profile_factory.h"

namespace sss {
namespace {

// A profile that is exactly a sum of Gaussians: the fit must find it with K <= its size.
class GaussianSumProfile final : public DiffusionProfile {
 public:
  explicit GaussianSumProfile(GaussianSum sum) : sum_(std::move(sum)) {}
  std::string name() const override { return "gaussians"; }
  glm::dvec3 evaluate(double r) const override { return sum_.evaluate(r); }
  glm::dvec3 totalReflectance() const override { return sum_.totalReflectance(); }
  glm::dvec3 integrateDisc(double rho) const override { return sum_.integrateDisc(rho); }

 private:
  GaussianSum sum_;
};

TEST(Gaussian, NormalizedAndDiscIntegral) {
  for (double v : {0.01, 1.0, 30.0}) {
    // integral_0^rho 2 pi r G dr by midpoint rule
    for (double rho : {0.5 * std::sqrt(v), 2.0 * std::sqrt(v), 10.0 * std::sqrt(v)}) {
      const int n = 20000;
      double sum = 0.0;
      for (int i = 0; i < n; ++i) {
        const double r = (i + 0.5) * rho / n;
        sum += 2.0 * M_PI * r * normalizedGaussian(v, r) * rho / n;
      }
      EXPECT_NEAR(sum, gaussianDiscIntegral(v, rho), 1e-7);
    }
    EXPECT_NEAR(gaussianDiscIntegral(v, 1e3 * std::sqrt(v)), 1.0, 1e-15);
    EXPECT_NEAR(gaussianDiscIntegral(v, gaussianCutoffRadius(v, 1e-3)), 1.0 - 1e-3, 1e-12);
  }
  EXPECT_DOUBLE_EQ(normalizedGaussian(2.0, 0.0), 1.0 / (4.0 * M_PI));
}

// Locks the normalization: the 2D convolution of G(v1) and G(v2), computed by brute force on a
// grid, is G(v1 + v2) (with the paper's unnormalized Eq. 9 it would be off by v1 v2 / (v1+v2)).
TEST(Gaussian, CompositionOnAGrid) {
  const double v1 = 0.7, v2 = 1.8, h = 0.05, extent = 12.0;
  const int n = static_cast<int>(2 * extent / h);
  for (double px : {0.0, 0.8, 2.5}) {
    const double py = 0.3;
    double conv = 0.0;
    for (int i = 0; i < n; ++i) {
      const double x = -extent + (i + 0.5) * h;
      for (int j = 0; j < n; ++j) {
        const double y = -extent + (j + 0.5) * h;
        const double a = normalizedGaussian(v1, std::hypot(x, y));
        const double b = normalizedGaussian(v2, std::hypot(px - x, py - y));
        conv += a * b * h * h;
      }
    }
    const double expected = normalizedGaussian(v1 + v2, std::hypot(px, py));
    EXPECT_NEAR(conv / expected, 1.0, 1e-6) << "at " << px;
  }
}

TEST(GaussianSumFit, RecoversAnExactSum) {
  GaussianSum truth;
  truth.variances = {0.04, 1.5};
  truth.weights = {glm::dvec3(0.3, 0.1, 0.05), glm::dvec3(0.4, 0.2, 0.6)};
  const GaussianSumProfile profile(truth);
  const GaussianSumFit fit = fitGaussians(profile, 1e-3);
  EXPECT_TRUE(fit.metTolerance);
  EXPECT_LE(fit.sum.size(), 2u);
  EXPECT_LE(fit.error, 1e-3);
  for (double r : {0.0, 0.1, 0.5, 1.0, 3.0})
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(fit.sum.evaluate(r)[c], truth.evaluate(r)[c], 0.01 * truth.evaluate(r)[c] + 1e-6)
          << r;
}

// The fit meets its tolerance for every preset, from very translucent (skimmilk) to dense
// (ketchup), for every profile; the energy is preserved exactly and the reported error is the
// metric recomputed independently.
TEST(GaussianSumFit, MeetsToleranceForEveryPresetAndProfile) {
  for (const Material& m : materialPresets()) {
    for (const std::string& kind : listProfiles()) {
      const auto profile = makeProfile(kind, m);
      const GaussianSumFit fit = fitGaussians(*profile, 0.01);
      SCOPED_TRACE(m.name + " " + kind);
      EXPECT_TRUE(fit.metTolerance);
      EXPECT_LE(fit.error, 0.01);
      EXPECT_GE(fit.sum.size(), 2u);
      EXPECT_LE(fit.sum.size(), 16u);
      const glm::dvec3 total = profile->totalReflectance(), fitted = fit.sum.totalReflectance();
      const glm::dvec3 recomputed = gaussianSumError(fit.sum, *profile);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(fitted[c] / total[c], 1.0, 1e-12);
        EXPECT_NEAR(recomputed[c], fit.channelError[c], 1e-12);
        EXPECT_LT(std::abs(fit.totalErrorBeforeScaling[c]), 0.02);
      }
      for (std::size_t k = 0; k < fit.sum.size(); ++k) {
        EXPECT_GT(fit.sum.variances[k], 0.0);
        if (k) {
          EXPECT_GT(fit.sum.variances[k], fit.sum.variances[k - 1]);
        }
        for (int c = 0; c < 3; ++c) EXPECT_GE(fit.sum.weights[k][c], 0.0);
      }
    }
  }
}

TEST(GaussianSumFit, TighterToleranceNeedsMoreGaussians) {
  const auto dipole = makeProfile("dipole", findMaterialPreset("marble"));
  const GaussianSumFit loose = fitGaussians(*dipole, 0.05);
  const GaussianSumFit tight = fitGaussians(*dipole, 0.003);
  EXPECT_TRUE(loose.metTolerance);
  EXPECT_TRUE(tight.metTolerance);
  EXPECT_LT(loose.sum.size(), tight.sum.size());
  // An unreachable tolerance returns the best fit and says so.
  const GaussianSumFit capped = fitGaussians(*dipole, 1e-6, 2);
  EXPECT_FALSE(capped.metTolerance);
  EXPECT_LE(capped.sum.size(), 2u);
  EXPECT_GT(capped.error, 1e-6);
}

}  // namespace
}  // namespace sss

namespace sss {
namespace {

// The escape energy model's wide kernel as a profile: a normalized Gaussian integrates to 1, its
// disc has the closed form, and the fit for the fast methods is that one Gaussian.
TEST(GaussianProfile, IsOneNormalizedGaussian) {
  const double variance = 37.0;  // mm^2
  const GaussianProfile g(variance);
  const double sigma = std::sqrt(variance);
  EXPECT_NEAR(integrateProfileNumerically(g, 0.0, 12.0 * sigma).x, 1.0, 1e-6);
  for (double rho : {0.5, 3.0, 9.0})
    EXPECT_NEAR(g.integrateDisc(rho).y, integrateProfileNumerically(g, 0.0, rho).y, 1e-6) << rho;
  EXPECT_NEAR(g.evaluate(sigma).z, std::exp(-0.5) / (2.0 * M_PI * variance), 1e-12);
  const GaussianSumFit fit = fitGaussians(g, 0.005);
  ASSERT_EQ(fit.sum.size(), 1u);
  EXPECT_NEAR(fit.sum.variances[0], variance, 0.01 * variance);  // within the fit tolerance
  EXPECT_NEAR(fit.sum.weights[0].x, 1.0, 1e-9);
  EXPECT_THROW(GaussianProfile(0.0), Error);
  EXPECT_THROW(GaussianProfile(std::nan("")), Error);
}

}  // namespace
}  // namespace sss
