// Sum-of-Gaussians approximation of a diffusion profile (Li & Guo Eq. 8), so that the diffusion
// sum can be computed with separable, incremental Gaussian convolutions (Li & Guo Eq. 11).
//
// Correction to Li & Guo: their Eq. 9, G(v,r) = e^{-r^2/2v} / (2 pi), drops the 1/v. We use the
// normalized 2D Gaussian
//   G(v, r) = e^{-r^2 / 2v} / (2 pi v),  integral_0^inf 2 pi r G dr = 1,
// so G(v1) * G(v2) = G(v1 + v2) under 2D convolution and the total reflectance of a sum is the
// sum of its weights. Variances (mm^2) are shared by R, G, B; weights are per channel.
//
// Fit (in the spirit of d'Eon & Luebke, GPU Gems 3 ch. 14): for a given K the variances form a
// geometric ladder whose two ends are optimized (Nelder-Mead), the weights of each channel
// solving a non-negative least-squares problem (Lawson-Hanson) on the samples below plus one
// row for the energy inside the innermost sample radius (so narrow Gaussians cannot hide
// energy near r = 0). The fewest K is found by doubling then bisection; one K fewer is then
// tried with every log-variance free (Nelder-Mead). Finally the weights of each channel are
// scaled so that their sum equals the profile's total reflectance exactly (energy preserved);
// the error is measured after that scaling.
//
// Error metric (what matters downstream: where the energy lands): per channel, the relative RMS
// of the radially weighted profile r R_d(r), on 64 log-spaced radii over
// [1e-3 r_999, r_999], r_999 the radius holding 99.9% of the channel's energy (quadrature of
// the integrals in dr):
//   e_c = sqrt( int (r (S(r) - R(r)))^2 dr / int (r R(r))^2 dr ),  error = max_c e_c.
// The K each profile needs and the fit times: docs/performance.md, "Material fits"
// (tests/bench/results/material/fits.csv).
#pragma once

#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "material/diffusion_profile.h"

namespace sss {

// Normalized 2D Gaussian of variance v (mm^2) at distance r (mm), in mm^-2.
double normalizedGaussian(double v, double r);
// integral_0^rho 2 pi r G(v, r) dr = 1 - e^{-rho^2 / 2v}.
double gaussianDiscIntegral(double v, double rho);
// Radius beyond which G(v) holds the fraction `tail` of its energy: sqrt(-2 v ln tail).
double gaussianCutoffRadius(double v, double tail);

struct GaussianSum {
  std::vector<double> variances;    // mm^2, ascending
  std::vector<glm::dvec3> weights;  // per Gaussian, per channel (dimensionless, >= 0)

  std::size_t size() const { return variances.size(); }
  glm::dvec3 evaluate(double rMm) const;
  glm::dvec3 totalReflectance() const;  // sum of weights
  glm::dvec3 integrateDisc(double rhoMm) const;
};

struct GaussianSumFit {
  GaussianSum sum;
  std::string profileName;
  double tolerance = 0.0;
  double error = 0.0;            // max over channels of the metric above
  glm::dvec3 channelError{0.0};  // e_c per channel
  // Relative total-reflectance error of the unconstrained fit before the energy scaling
  // (the scaling removes it; reported so a poor fit is visible).
  glm::dvec3 totalErrorBeforeScaling{0.0};
  bool metTolerance = false;  // false: maxGaussians reached, best fit returned
  double fitSeconds = 0.0;
};

// The fewest Gaussians (<= maxGaussians) whose error <= tolerance (e.g. 0.01). Never throws for
// a valid profile; if the tolerance is not met, returns the best fit with metTolerance = false.
GaussianSumFit fitGaussians(const DiffusionProfile& profile, double tolerance,
                            int maxGaussians = 16);

// The fit's error metric for any sum against any profile (tests and reports).
glm::dvec3 gaussianSumError(const GaussianSum& sum, const DiffusionProfile& profile);

}  // namespace sss
