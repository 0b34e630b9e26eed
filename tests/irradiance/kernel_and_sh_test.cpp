// The transmitted-cosine kernel and the spherical harmonics against closed forms.
#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "irradiance/brute_force.h"
#include "irradiance/spherical_harmonics.h"
#include "irradiance/transmitted_cosine.h"
#include "optics/fresnel.h"

namespace sss {
namespace {

// 2 pi int_0^1 mu F_t(mu) P_l(mu) dmu by the midpoint rule, for the checks below.
double zonalByQuadrature(int l, float eta) {
  const int n = 200000;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const double mu = (i + 0.5) / n;
    double p0 = 1.0, p1 = mu;
    for (int k = 2; k <= l; ++k) {
      const double p2 = ((2 * k - 1) * mu * p1 - (k - 1) * p0) / k;
      p0 = p1;
      p1 = p2;
    }
    const double pl = l == 0 ? 1.0 : p1;
    sum += mu * (eta == 1.0f ? 1.0 : fresnelTransmittance(static_cast<float>(mu), eta)) * pl;
  }
  return 2.0 * M_PI * sum / n;
}

TEST(TransmittedCosineKernel, ZonalCoefficients) {
  const TransmittedCosineKernel plain(1.0f);
  // Ramamoorthi & Hanrahan 2001, Eq. 9: pi, 2 pi / 3, pi / 4, 0, -pi / 24.
  EXPECT_DOUBLE_EQ(plain.zonalCoefficient(0), M_PI);
  EXPECT_DOUBLE_EQ(plain.zonalCoefficient(1), 2.0 * M_PI / 3.0);
  EXPECT_DOUBLE_EQ(plain.zonalCoefficient(2), M_PI / 4.0);
  EXPECT_DOUBLE_EQ(plain.zonalCoefficient(3), 0.0);
  EXPECT_NEAR(plain.zonalCoefficient(4), -M_PI / 24.0, 1e-15);
  for (int l = 0; l <= 8; ++l)
    EXPECT_NEAR(plain.zonalCoefficient(l), zonalByQuadrature(l, 1.0f), 1e-8) << l;
  for (float eta : {1.33f, 1.5f, 0.75f}) {
    const TransmittedCosineKernel k(eta);
    // The l = 0 term is the hemispherical transmittance: pi (1 - 2 C_1) (both quadratures meet
    // the critical-angle kink for eta < 1: a few 1e-5).
    EXPECT_NEAR(k.zonalCoefficient(0), M_PI * (1.0 - diffuseFresnelReflectance(eta)), 3e-5);
    for (int l = 0; l <= 6; ++l)
      EXPECT_NEAR(k.zonalCoefficient(l), zonalByQuadrature(l, eta), 1e-5) << l;
  }
}

TEST(TransmittedCosineKernel, TableMatchesExactFresnel) {
  EXPECT_EQ(TransmittedCosineKernel(1.0f).transmittance(0.3f), 1.0f);
  const TransmittedCosineKernel k(1.4f);
  for (float mu = 0.0f; mu <= 1.0f; mu += 0.0137f) {
    EXPECT_NEAR(k.transmittance(mu), fresnelTransmittance(mu, 1.4f), 2e-6) << mu;
    EXPECT_NEAR(k(mu), mu * fresnelTransmittance(mu, 1.4f), 2e-6) << mu;
  }
  EXPECT_EQ(k(-0.2f), 0.0f);
}

TEST(SphericalHarmonics, BasisMatchesClosedFormsAndIsOrthonormal) {
  // Closed forms of bands 0-3 (Sloan 2008), through the general recurrence of order 4.
  const glm::vec3 d = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
  float y[25];
  SphericalHarmonics::evaluateBasis(4, d, y);
  const float expected[9] = {0.282095f,
                             0.488603f * d.y,
                             0.488603f * d.z,
                             0.488603f * d.x,
                             1.092548f * d.x * d.y,
                             1.092548f * d.y * d.z,
                             0.315392f * (3 * d.z * d.z - 1),
                             1.092548f * d.x * d.z,
                             0.546274f * (d.x * d.x - d.y * d.y)};
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(y[i], expected[i], 2e-6) << i;
  const float band3[7] = {
      0.590044f * d.y * (3 * d.x * d.x - d.y * d.y), 2.890611f * d.x * d.y * d.z,
      0.457046f * d.y * (5 * d.z * d.z - 1),         0.373176f * d.z * (5 * d.z * d.z - 3),
      0.457046f * d.x * (5 * d.z * d.z - 1),         1.445306f * d.z * (d.x * d.x - d.y * d.y),
      0.590044f * d.x * (d.x * d.x - 3 * d.y * d.y)};
  for (int i = 0; i < 7; ++i) EXPECT_NEAR(y[9 + i], band3[i], 2e-6) << 9 + i;
  // The closed forms the low orders take agree with the recurrence of order 4 (directions off
  // every axis and plane, so that no basis function vanishes).
  for (const glm::vec3 w : {d, glm::normalize(glm::vec3(-0.7f, 0.2f, -0.4f)),
                            glm::normalize(glm::vec3(0.1f, 0.9f, -0.3f))}) {
    float full[25], low[16];
    SphericalHarmonics::evaluateBasis(4, w, full);
    SphericalHarmonics::evaluateBasis(3, w, low);
    for (int i = 0; i < 16; ++i) EXPECT_NEAR(low[i], full[i], 2e-6) << i;
    SphericalHarmonics::evaluateBasis(2, w, low);
    for (int i = 0; i < 9; ++i) EXPECT_NEAR(low[i], full[i], 2e-6) << i;
  }

  // Orthonormality up to order 6 by cubemap quadrature.
  const int order = 6, count = 49, n = 64;
  Cubemap grid(n);
  std::vector<double> gram(count * count, 0.0);
  std::vector<float> b(count);
  for (int f = 0; f < 6; ++f) {
    for (int yy = 0; yy < n; ++yy) {
      for (int x = 0; x < n; ++x) {
        SphericalHarmonics::evaluateBasis(order, grid.direction(f, x, yy), b.data());
        const double w = grid.solidAngle(f, x, yy);
        for (int i = 0; i < count; ++i) {
          for (int j = 0; j < count; ++j) gram[i * count + j] += w * b[i] * b[j];
        }
      }
    }
  }
  for (int i = 0; i < count; ++i) {
    for (int j = 0; j < count; ++j)
      EXPECT_NEAR(gram[i * count + j], i == j ? 1.0 : 0.0, 2e-3) << i << "," << j;
  }
}

TEST(SphericalHarmonics, ProjectionReproducesABandLimitedFunction) {
  // L(w) = 1 + 0.5 x - 0.3 z + 0.2 x y lies in bands 0-2: projection and evaluation give it back.
  auto radiance = [](const glm::vec3& w) {
    return 1.0f + 0.5f * w.x - 0.3f * w.z + 0.2f * w.x * w.y;
  };
  Cubemap cube(48);
  forEachTexel(48, [&](int f, int x, int y) {
    cube.at(f, x, y) = glm::vec3(radiance(cube.direction(f, x, y)));
  });
  const SphericalHarmonics sh = SphericalHarmonics::project(cube, 4);
  for (const glm::vec3& d : fibonacciSphere(50)) EXPECT_NEAR(sh.evaluate(d).x, radiance(d), 2e-3);
  // The same from an equirect image.
  ImageRgb image;
  image.width = 256;
  image.height = 128;
  image.pixels.resize(256 * 128);
  for (int y = 0; y < 128; ++y) {
    for (int x = 0; x < 256; ++x) {
      const double phi = 2 * M_PI * ((x + 0.5) / 256 - 0.5), theta = M_PI * (y + 0.5) / 128;
      image.at(x, y) = glm::vec3(radiance(glm::vec3(
          std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi))));
    }
  }
  const SphericalHarmonics fromImage = SphericalHarmonics::projectEquirect(image, 2);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(fromImage[i].x, sh[i].x, 2e-3) << i;
}

TEST(SphericalHarmonics, WindowsDampHighBands) {
  for (ShWindow w : {ShWindow::Hann, ShWindow::Lanczos}) {
    EXPECT_DOUBLE_EQ(shWindowWeight(w, 0, 2), 1.0);
    EXPECT_LT(shWindowWeight(w, 2, 2), shWindowWeight(w, 1, 2));
    EXPECT_GT(shWindowWeight(w, 2, 2), 0.0);
  }
  EXPECT_DOUBLE_EQ(shWindowWeight(ShWindow::None, 2, 2), 1.0);
  EXPECT_NEAR(shWindowWeight(ShWindow::Hann, 1, 2), 0.75, 1e-12);  // (1 + cos(pi / 3)) / 2
  EXPECT_EQ(kShWindowNames.parse("lanczos"), ShWindow::Lanczos);
}

}  // namespace
}  // namespace sss
