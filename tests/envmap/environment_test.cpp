// The equirect convention, equirect/cross/stack -> cubemap conversion and their round trips.
#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "envmap/environment.h"
#include "envmap/equirect.h"
#include "expect_near.h"

namespace sss {
namespace {

using test::expectNear;

// Colour by direction: +X red, +Y green, +Z blue; the negative axes are dimmer mixes, so that
// every axis has its own colour.
glm::vec3 directionColour(const glm::vec3& d) {
  return glm::max(d, glm::vec3(0.0f)) +
         0.25f * glm::vec3(std::max(-d.y, 0.0f) + std::max(-d.z, 0.0f),
                           std::max(-d.x, 0.0f) + std::max(-d.z, 0.0f),
                           std::max(-d.x, 0.0f) + std::max(-d.y, 0.0f));
}

ImageRgb directionColouredEquirect(int width) {
  ImageRgb image;
  image.width = width;
  image.height = width / 2;
  image.pixels.resize(static_cast<std::size_t>(image.width) * image.height);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      image.at(x, y) =
          directionColour(equirectDirection((x + 0.5f) / image.width, (y + 0.5f) / image.height));
    }
  }
  return image;
}

TEST(Equirect, ConventionIsLocked) {
  expectNear(equirectDirection(0.5f, 0.5f), {0, 0, -1}, 1e-6f);  // image centre looks to -Z
  expectNear(equirectDirection(0.75f, 0.5f), {1, 0, 0}, 1e-6f);  // right of centre: +X
  expectNear(equirectDirection(0.25f, 0.5f), {-1, 0, 0}, 1e-6f);
  expectNear(equirectDirection(0.0f, 0.5f), {0, 0, 1}, 1e-6f);
  expectNear(equirectDirection(0.3f, 0.0f), {0, 1, 0}, 1e-6f);  // top row: up
  expectNear(equirectDirection(0.3f, 1.0f), {0, -1, 0}, 1e-6f);
}

TEST(Equirect, CoordInvertsDirection) {
  for (float u = 0.01f; u < 1.0f; u += 0.07f) {
    for (float v = 0.02f; v < 1.0f; v += 0.09f) {
      const glm::vec2 uv = equirectCoord(2.0f * equirectDirection(u, v));
      EXPECT_NEAR(uv.x, u, 1e-5);
      EXPECT_NEAR(uv.y, v, 1e-5);
    }
  }
}

TEST(Environment, DetectLayout) {
  EXPECT_EQ(detectLayout("a", 1024, 512), EnvironmentLayout::Equirect);
  EXPECT_EQ(detectLayout("a", 256, 192), EnvironmentLayout::Cross);
  EXPECT_EQ(detectLayout("a", 192, 256), EnvironmentLayout::Cross);
  EXPECT_EQ(detectLayout("a", 64, 384), EnvironmentLayout::CubemapStack);
  try {
    detectLayout("env.exr", 100, 30);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("env.exr: unsupported shape 100x30", 0), 0u) << e.what();
  }
  EXPECT_THROW(detectLayout("a", 0, 0), Error);
}

TEST(Environment, DirectionColouredEquirectLandsOnTheRightFacesAndTexels) {
  const Cubemap cube =
      cubemapFromImage(directionColouredEquirect(512), EnvironmentLayout::Equirect, 32);
  // Face centres carry their axis' colour.
  const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int f = 0; f < 6; ++f) {
    const glm::vec3 centre =
        0.25f * (cube.at(f, 15, 15) + cube.at(f, 16, 15) + cube.at(f, 15, 16) + cube.at(f, 16, 16));
    expectNear(centre, directionColour(axes[f]), 0.03f);
  }
  // Every texel holds the colour of its own direction.
  float worst = 0.0f;
  forEachTexel(32, [&](int f, int x, int y) {
    worst =
        std::max(worst, glm::length(cube.at(f, x, y) - directionColour(cube.direction(f, x, y))));
  });
  EXPECT_LT(worst, 0.03f);
}

TEST(Environment, EquirectToCubemapToLookupRoundTrip) {
  const ImageRgb image = directionColouredEquirect(512);
  const Cubemap cube = cubemapFromImage(image, EnvironmentLayout::Equirect, 64);
  float worst = 0.0f;
  for (int y = 8; y < image.height; y += 16) {
    for (int x = 3; x < image.width; x += 16) {
      const glm::vec3 d = equirectDirection((x + 0.5f) / image.width, (y + 0.5f) / image.height);
      worst = std::max(worst, glm::length(cube.sample(d) - image.at(x, y)));
    }
  }
  EXPECT_LT(worst, 0.03f);
}

TEST(Environment, EquirectToCubemapKeepsFlux) {
  ImageRgb image = directionColouredEquirect(256);
  image.at(100, 40) = glm::vec3(500.0f);  // a small bright source
  glm::dvec3 flux(0.0);
  for (int y = 0; y < image.height; ++y) {
    const double omega =
        2.0 * M_PI / image.width *
        (std::cos(M_PI * y / image.height) - std::cos(M_PI * (y + 1) / image.height));
    for (int x = 0; x < image.width; ++x) flux += omega * glm::dvec3(image.at(x, y));
  }
  const Cubemap cube = cubemapFromImage(image, EnvironmentLayout::Equirect, 0);
  EXPECT_EQ(cube.size(), 64);
  glm::dvec3 cubeFlux(0.0);
  forEachTexel(cube.size(), [&](int f, int x, int y) {
    cubeFlux += glm::dvec3(cube.at(f, x, y)) * double(cube.solidAngle(f, x, y));
  });
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(cubeFlux[k], flux[k], 0.01 * flux[k]);
}

Cubemap numberedCubemap(int n) {
  Cubemap cube(n);
  forEachTexel(n, [&](int f, int x, int y) { cube.at(f, x, y) = glm::vec3(f, x, y); });
  return cube;
}

void expectSameCubemap(const Cubemap& a, const Cubemap& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.texelCount(); ++i) ASSERT_EQ(a.data()[i], b.data()[i]) << i;
}

TEST(Environment, CrossAndStackRoundTrips) {
  const Cubemap cube = numberedCubemap(8);
  const ImageRgb cross = cubemapToCross(cube);
  EXPECT_EQ(cross.width, 32);
  EXPECT_EQ(cross.height, 24);
  expectSameCubemap(cubemapFromImage(cross, detectLayout("", cross.width, cross.height), 0), cube);
  const ImageRgb stack = cubemapToStack(cube);
  EXPECT_EQ(stack.height, 48);
  expectSameCubemap(cubemapFromImage(stack, detectLayout("", stack.width, stack.height), 0), cube);
}

// The unfolded cross is continuous: texels that touch across a face edge in the image look in
// almost the same direction (horizontal cross, and the vertical cross built by hand).
TEST(Environment, CrossesAreContinuous) {
  const int n = 16;
  Cubemap geometry(n);
  Cubemap dirs(n);
  forEachTexel(n, [&](int f, int x, int y) { dirs.at(f, x, y) = geometry.direction(f, x, y); });
  const ImageRgb cross = cubemapToCross(dirs);
  const float maxStep = 2.5f / n;  // neighbouring texels are < 2 / n radians apart
  auto check = [&](const ImageRgb& img) {
    int pairs = 0;
    for (int y = 0; y + 1 < img.height; ++y) {
      for (int x = 0; x + 1 < img.width; ++x) {
        const glm::vec3 a = img.at(x, y), r = img.at(x + 1, y), d = img.at(x, y + 1);
        if (glm::length(a) > 0.5f && glm::length(r) > 0.5f) {
          EXPECT_LT(glm::length(a - r), maxStep) << x << "," << y;
          ++pairs;
        }
        if (glm::length(a) > 0.5f && glm::length(d) > 0.5f) {
          EXPECT_LT(glm::length(a - d), maxStep) << x << "," << y;
          ++pairs;
        }
      }
    }
    EXPECT_GT(pairs, 10 * n * n);
  };
  check(cross);

  // Vertical cross: the horizontal one's middle column with -Z below -Y, turned by 180 degrees.
  ImageRgb vertical;
  vertical.width = 3 * n;
  vertical.height = 4 * n;
  vertical.pixels.assign(static_cast<std::size_t>(vertical.width) * vertical.height, glm::vec3(0));
  for (int y = 0; y < 3 * n; ++y) {
    for (int x = 0; x < 3 * n; ++x) vertical.at(x, y) = cross.at(x, y);
  }
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) vertical.at(2 * n - 1 - x, 4 * n - 1 - y) = dirs.at(5, x, y);
  }
  check(vertical);
  expectSameCubemap(
      cubemapFromImage(vertical, detectLayout("", vertical.width, vertical.height), 0), dirs);
}

}  // namespace
}  // namespace sss
