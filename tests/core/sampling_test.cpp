// The direction samplers of lib/core/sampling.h against their pdfs: each pdf integrates to 1 over
// its domain, and the samples' histogram in the cosine to the axis (and in the azimuth, for the
// hemisphere mappings) matches the pdf by Pearson's chi-square.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "core/random.h"
#include "core/sampling.h"

namespace sss {
namespace {

// A pdf per steradian that depends on the cosine mu to the axis only.
using CosinePdf = std::function<double(double mu)>;

// The probability of mu in [lo, hi]: 2 pi times the integral of the pdf over mu (midpoint rule,
// `nodes` nodes; the pdfs here are smooth within a bin).
double probabilityIn(const CosinePdf& pdf, double lo, double hi, int nodes = 4000) {
  const double h = (hi - lo) / nodes;
  double sum = 0.0;
  for (int i = 0; i < nodes; ++i) sum += pdf(lo + (i + 0.5) * h);
  return 2.0 * M_PI * sum * h;
}

// Pearson's chi-square of observed counts against expected ones, over bins expecting at least 5.
struct ChiSquare {
  double statistic = 0.0;
  int bins = 0;
  void add(double observed, double expected) {
    if (expected < 5.0) return;
    statistic += (observed - expected) * (observed - expected) / expected;
    ++bins;
  }
  // Fails above the mean plus 6 standard deviations of the chi-square distribution of bins - 1
  // degrees of freedom: a correct sampler passes with certainty for a fixed seed, and a wrong
  // mapping (a pdf off by a few percent in a bin of 1 % of 400K samples) lands far above it.
  void expectConsistent(const char* what) const {
    ASSERT_GT(bins, 1) << what;
    const double dof = bins - 1;
    EXPECT_LT(statistic, dof + 6.0 * std::sqrt(2.0 * dof)) << what << ": " << bins << " bins";
  }
};

constexpr int kSamples = 400000;
constexpr int kCosineBins = 40;

// Chi-square of the cosines to `axis` of kSamples draws, in kCosineBins equal bins of
// [muMin, 1], against pdf.
void expectCosinesFollow(const std::function<glm::vec3(Pcg32&)>& sample, const glm::vec3& axis,
                         const CosinePdf& pdf, double muMin, const char* what) {
  Pcg32 rng(12345, 0);
  std::vector<double> counts(kCosineBins, 0.0);
  const double width = (1.0 - muMin) / kCosineBins;
  for (int i = 0; i < kSamples; ++i) {
    const glm::vec3 d = sample(rng);
    ASSERT_NEAR(glm::length(d), 1.0f, 1e-5f) << what;
    const double mu = glm::dot(d, axis);
    ASSERT_GE(mu, muMin - 1e-6) << what;
    const int bin = std::clamp(int((mu - muMin) / width), 0, kCosineBins - 1);
    counts[bin] += 1.0;
  }
  ChiSquare chi;
  for (int b = 0; b < kCosineBins; ++b)
    chi.add(counts[b], kSamples * probabilityIn(pdf, muMin + b * width, muMin + (b + 1) * width));
  chi.expectConsistent(what);
}

// Chi-square of the azimuths about +Z of kSamples draws in 16 bins against uniform: the density
// depends on the cosine only.
void expectAzimuthUniform(const std::function<glm::vec3(Pcg32&)>& sample, const char* what) {
  constexpr int kBins = 16;
  Pcg32 rng(777, 0);
  std::vector<double> counts(kBins, 0.0);
  for (int i = 0; i < kSamples; ++i) {
    const glm::vec3 d = sample(rng);
    const double phi = std::atan2(double(d.y), double(d.x)) + M_PI;  // [0, 2 pi]
    counts[std::clamp(int(phi / (2.0 * M_PI) * kBins), 0, kBins - 1)] += 1.0;
  }
  ChiSquare chi;
  for (int b = 0; b < kBins; ++b) chi.add(counts[b], double(kSamples) / kBins);
  chi.expectConsistent(what);
}

const glm::vec3 kTilted = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));

CosinePdf cosinePdf() {
  return [](double mu) { return double(cosineHemispherePdf(float(mu))); };
}

TEST(Sampling, PdfsIntegrateToOne) {
  EXPECT_NEAR(probabilityIn(cosinePdf(), -1.0, 1.0, 200000), 1.0, 1e-4);
  for (double cosMax : {-0.5, 0.0, 0.9, 0.999}) {
    const CosinePdf cone = [cosMax](double) { return uniformConePdf(cosMax); };
    EXPECT_NEAR(probabilityIn(cone, cosMax, 1.0), 1.0, 1e-9) << cosMax;
  }
  // Strongly forward or backward lobes need fine nodes near mu = +-1.
  for (double g : {-0.9, -0.3, 0.0, 0.5, 0.9}) {
    const CosinePdf hg = [g](double mu) { return henyeyGreensteinPdf(g, mu); };
    EXPECT_NEAR(probabilityIn(hg, -1.0, 1.0, 2000000), 1.0, 1e-5) << g;
  }
}

TEST(Sampling, ConcentricCosineHemisphereFollowsItsPdf) {
  const auto sample = [](Pcg32& rng) {
    const float u1 = rng.uniform(), u2 = rng.uniform();
    return sampleCosineHemisphereConcentric(u1, u2);
  };
  expectCosinesFollow(sample, glm::vec3(0, 0, 1), cosinePdf(), 0.0, "concentric");
  expectAzimuthUniform(sample, "concentric");
}

TEST(Sampling, PolarCosineHemisphereFollowsItsPdf) {
  expectCosinesFollow([](Pcg32& rng) { return sampleCosineHemispherePolar(kTilted, rng); }, kTilted,
                      cosinePdf(), 0.0, "polar");
  expectAzimuthUniform(
      [](Pcg32& rng) { return sampleCosineHemispherePolar(glm::vec3(0, 0, 1), rng); }, "polar");
}

TEST(Sampling, UniformConeFollowsItsPdf) {
  for (double cosMax : {-0.5, 0.3, 0.99}) {
    const auto sample = [cosMax](Pcg32& rng) {
      const double u1 = rng.uniformDouble(), u2 = rng.uniformDouble();
      return sampleUniformCone(kTilted, cosMax, u1, u2);
    };
    const CosinePdf pdf = [cosMax](double) { return uniformConePdf(cosMax); };
    expectCosinesFollow(sample, kTilted, pdf, cosMax, "cone");
  }
}

TEST(Sampling, HenyeyGreensteinFollowsItsPdf) {
  for (double g : {-0.7, 0.0, 0.3, 0.85}) {
    const auto sample = [g](Pcg32& rng) { return sampleHenyeyGreenstein(kTilted, g, rng); };
    const CosinePdf pdf = [g](double mu) { return henyeyGreensteinPdf(g, mu); };
    expectCosinesFollow(sample, kTilted, pdf, -1.0, "Henyey-Greenstein");
  }
}

// The chi-square check can fail: a cosine-weighted sampler's cosines against the uniform cone's
// pdf over the hemisphere land far above the bound.
TEST(Sampling, ChiSquareRejectsTheWrongPdf) {
  Pcg32 rng(5, 0);
  std::vector<double> counts(kCosineBins, 0.0);
  for (int i = 0; i < kSamples; ++i) {
    const double mu = glm::dot(sampleCosineHemispherePolar(kTilted, rng), kTilted);
    counts[std::clamp(int(mu * kCosineBins), 0, kCosineBins - 1)] += 1.0;
  }
  const CosinePdf uniform = [](double) { return uniformConePdf(0.0); };
  ChiSquare chi;
  for (int b = 0; b < kCosineBins; ++b)
    chi.add(counts[b], kSamples * probabilityIn(uniform, double(b) / kCosineBins,
                                                double(b + 1) / kCosineBins));
  const double dof = chi.bins - 1;
  EXPECT_GT(chi.statistic, dof + 6.0 * std::sqrt(2.0 * dof));
}

}  // namespace
}  // namespace sss
