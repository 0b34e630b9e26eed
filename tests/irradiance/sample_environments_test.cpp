// The sample HDRs (data/fetch.sh): SH order 2 against the direct sum, with Ramamoorthi &
// Hanrahan 2001's error measures (Section 3): errors relative to the peak irradiance. For one
// directional source of flux Phi the 9-term irradiance is Phi (1/4 + mu/2 + 5/16 P_2(mu)) against
// Phi max(mu, 0): largest error 3/32 = 9.375% of Phi, mean absolute error 3.07% of Phi ("at most
// 9%", "average 3%"). The error is linear in the lighting, so any environment obeys
//   max |dE| <= 0.09375 Phi_total,   mean |dE| <= 0.0307 Phi_total,   Phi_total = int L dw,
// and R&H observe average errors near 1% of the peak on real maps.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "core/relative_rms.h"
#include "envmap/environment.h"
#include "image/image.h"
#include "irradiance/brute_force.h"
#include "irradiance/irradiance.h"

namespace sss {
namespace {

const char* const kMaps[] = {"city",  "courtyard", "forest",  "interior",
                             "night", "studio",    "sunrise", "sunset"};

std::string mapPath(const std::string& name) {
  return (std::filesystem::path(SSS_SOURCE_DIR) / "data/cache/env" / (name + ".exr")).string();
}

TEST(SampleEnvironments, ShOrderTwoWithinRamamoorthiHanrahanError) {
  for (const char* name : kMaps) {
    ASSERT_TRUE(std::filesystem::exists(mapPath(name)))
        << mapPath(name) << " missing: run data/fetch.sh";
    const Cubemap radiance = loadEnvironment(mapPath(name), {{}, 64});
    const std::vector<glm::vec3> normals = fibonacciSphere(1000);
    const std::vector<glm::vec3> exact = irradianceAtNormals(radiance, normals, 1.0f);
    const SphericalHarmonics sh =
        SphericalHarmonics::project(radiance, 2).convolved(TransmittedCosineKernel(1.0f));
    double flux = 0.0;
    forEachTexel(radiance.size(), [&](int f, int x, int y) {
      flux += glm::dot(radiance.at(f, x, y), glm::vec3(0.2126f, 0.7152f, 0.0722f)) *
              radiance.solidAngle(f, x, y);
    });
    double sumError = 0.0, maxError = 0.0, maxE = 0.0;
    for (std::size_t i = 0; i < normals.size(); ++i) {
      const double e = glm::dot(exact[i], glm::vec3(0.2126f, 0.7152f, 0.0722f));
      const double a = glm::dot(sh.evaluate(normals[i]), glm::vec3(0.2126f, 0.7152f, 0.0722f));
      sumError += std::abs(a - e);
      maxError = std::max(maxError, std::abs(a - e));
      maxE = std::max(maxE, e);
    }
    const double meanError = sumError / normals.size();
    EXPECT_LT(maxError, 0.09375 * flux) << name;
    EXPECT_LT(meanError, 0.0307 * flux) << name;
    // Against the peak, as R&H tabulate: within their one-light worst case, except in the studio,
    // whose several small lights each bring their own 3% of a peak they do not share.
    if (std::string(name) != "studio") {
      EXPECT_LT(meanError / maxE, 0.0307) << name;
    }
    std::printf("%-10s SH2 error: mean %.2f%%, max %.2f%% of the peak irradiance\n", name,
                100 * meanError / maxE, 100 * maxError / maxE);
  }
}

TEST(SampleEnvironments, BruteMeetsToleranceAndAutoExplainsItsChoice) {
  ASSERT_TRUE(std::filesystem::exists(mapPath("studio"))) << "run data/fetch.sh";
  const Cubemap radiance = loadEnvironment(mapPath("studio"), {{}, 128});
  IrradianceOptions o;
  const IrradianceResult r = computeIrradiance(radiance, o);
  EXPECT_LE(r.estimatedError, o.tolerance);
  EXPECT_FALSE(r.reason.empty());
  // Independent check on many normals, against the exact sum.
  const std::vector<glm::vec3> normals = fibonacciSphere(2000);
  std::vector<glm::vec3> looked(normals.size());
  for (std::size_t i = 0; i < normals.size(); ++i) looked[i] = r.irradiance.sample(normals[i]);
  EXPECT_LT(relativeRms(looked, irradianceAtNormals(radiance, normals, 1.0f)), 1.5 * o.tolerance);
}

// The exact sum over every texel of an equirect image, each with its solid angle, at `normals`,
// against `cube` through the renderer's bilinear lookup: relative RMS.
double errorAgainstEveryTexel(const ImageRgb& image, const Cubemap& cube,
                              const std::vector<glm::vec3>& normals) {
  const std::vector<glm::vec3> exact =
      irradianceAtNormals(RadianceGrid::fromEquirect(image, 1), normals, 1.0f);
  std::vector<glm::vec3> looked(normals.size());
  for (std::size_t i = 0; i < normals.size(); ++i) looked[i] = cube.sample(normals[i]);
  return relativeRms(looked, exact);
}

// Straight from the equirect rows (no radiance cubemap): the error auto reports (against the sum
// over 8 x 8-texel cells at its 256 probes) holds against the exact sum over every texel at 300
// other normals, at the tolerance cmft is compared at, with a bright small sun (sunrise), several
// small lights (studio), and a sky (forest). Measured: reported 0.09-0.16%, actual 0.1-0.15%.
TEST(SampleEnvironments, EquirectErrorReportedHoldsAgainstEveryTexel) {
  const std::vector<glm::vec3> normals = fibonacciSphere(300);
  for (const char* name : {"sunrise", "studio", "forest"}) {
    ASSERT_TRUE(std::filesystem::exists(mapPath(name))) << "run data/fetch.sh";
    const ImageRgb image = readImage(mapPath(name));
    IrradianceOptions o;
    o.faceSize = 32;
    const IrradianceResult r = computeIrradianceFromEquirect(image, o);
    EXPECT_LE(r.estimatedError, o.tolerance) << name;
    const double actual = errorAgainstEveryTexel(image, r.irradiance, normals);
    EXPECT_LE(actual, o.tolerance) << name;
    EXPECT_LE(actual, 1.5 * r.estimatedError) << name << " reported " << r.estimatedError;
  }
}

}  // namespace
}  // namespace sss
