// Cubemap geometry: the OpenGL face mapping, texel directions, solid angles, lookups.
#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "envmap/cubemap.h"
#include "envmap/equirect.h"
#include "expect_near.h"

namespace sss {
namespace {

using test::expectNear;

// OpenGL 4.5 table 8.19, read backwards: the (s, t) = (0, 0) corner of every face.
TEST(Cubemap, FaceCornersFollowOpenGl) {
  expectNear(Cubemap::unproject(0, 0, 0), {1, 1, 1}, 0);    // +X: sc = -z, tc = -y
  expectNear(Cubemap::unproject(1, 0, 0), {-1, 1, -1}, 0);  // -X: sc = +z, tc = -y
  expectNear(Cubemap::unproject(2, 0, 0), {-1, 1, -1}, 0);  // +Y: sc = +x, tc = +z
  expectNear(Cubemap::unproject(3, 0, 0), {-1, -1, 1}, 0);  // -Y: sc = +x, tc = -z
  expectNear(Cubemap::unproject(4, 0, 0), {-1, 1, 1}, 0);   // +Z: sc = +x, tc = -y
  expectNear(Cubemap::unproject(5, 0, 0), {1, 1, -1}, 0);   // -Z: sc = -x, tc = -y
  const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int f = 0; f < 6; ++f) {
    expectNear(Cubemap::unproject(f, 0.5f, 0.5f), axes[f], 0);
    const CubeCoord c = Cubemap::project(axes[f]);
    EXPECT_EQ(c.face, f);
    EXPECT_FLOAT_EQ(c.s, 0.5f);
    EXPECT_FLOAT_EQ(c.t, 0.5f);
  }
}

TEST(Cubemap, ProjectInvertsUnproject) {
  for (int f = 0; f < 6; ++f) {
    for (float s : {0.05f, 0.3f, 0.77f, 0.95f}) {
      for (float t : {0.1f, 0.5f, 0.9f}) {
        const CubeCoord c = Cubemap::project(3.0f * Cubemap::unproject(f, s, t));
        EXPECT_EQ(c.face, f);
        EXPECT_NEAR(c.s, s, 1e-6);
        EXPECT_NEAR(c.t, t, 1e-6);
      }
    }
  }
}

TEST(Cubemap, SolidAnglesSumToFourPi) {
  for (int n : {1, 3, 16, 33}) {
    Cubemap cube(n);
    double sum = 0.0;
    const std::vector<float> face = cube.faceSolidAngles();
    forEachTexel(n, [&](int f, int x, int y) {
      sum += cube.solidAngle(f, x, y);
      EXPECT_NEAR(face[y * n + x], cube.solidAngle(f, x, y), 1e-7);
    });
    EXPECT_NEAR(sum, 4.0 * M_PI, 1e-5) << "n = " << n;
  }
  // One texel per face: a sixth of the sphere.
  EXPECT_NEAR(Cubemap(1).solidAngle(0, 0, 0), 4.0 * M_PI / 6.0, 1e-6);
}

TEST(Cubemap, BilinearSampleIsSeamlessAndExactForLinearFunctions) {
  // A linear function of direction is reproduced at texel centres and stays continuous across
  // every face edge (corner texels included).
  const int n = 16;
  Cubemap cube(n);
  forEachTexel(
      n, [&](int f, int x, int y) { cube.at(f, x, y) = 0.5f * cube.direction(f, x, y) + 0.5f; });
  for (int f = 0; f < 6; ++f)
    expectNear(cube.sample(cube.direction(f, 5, 7)), cube.at(f, 5, 7), 1e-6f);
  float worst = 0.0f;
  for (int i = 0; i < 2000; ++i) {
    const glm::vec3 d =
        equirectDirection((i * 0.618034f) - std::floor(i * 0.618034f), (i + 0.5f) / 2000.0f);
    worst = std::max(worst, glm::length(cube.sample(d) - (0.5f * d + 0.5f)));
  }
  EXPECT_LT(worst, 0.02f);  // bilinear error of a unit-sphere function, texels 1/8 rad wide
}

TEST(Cubemap, ResizeKeepsFlux) {
  const int n = 32;
  Cubemap cube(n);
  forEachTexel(
      n, [&](int f, int x, int y) { cube.at(f, x, y) = glm::vec3(f + 1, x % 3, (x * y) % 5); });
  auto flux = [](const Cubemap& c) {
    glm::dvec3 sum(0.0);
    forEachTexel(c.size(), [&](int f, int x, int y) {
      sum += glm::dvec3(c.at(f, x, y)) * double(c.solidAngle(f, x, y));
    });
    return sum;
  };
  const glm::dvec3 before = flux(cube), after = flux(cube.resized(8));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(after[k], before[k], 1e-5 * before[k]);
}

}  // namespace
}  // namespace sss
