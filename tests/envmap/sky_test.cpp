// The procedural sun and sky of --sky.
#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/luminance.h"
#include "envmap/environment.h"

namespace sss {
namespace {

TEST(Sky, SpecSetsSunDirectionAndParameters) {
  const SkyParameters sky =
      parseSkySpec("elevation=30,azimuth=90,turbidity=5,sun=2,radius=1,ground=0.5");
  EXPECT_NEAR(sky.sunDirection.x, std::cos(M_PI / 6), 1e-6);  // azimuth 90: towards +X
  EXPECT_NEAR(sky.sunDirection.y, 0.5, 1e-6);
  EXPECT_NEAR(sky.sunDirection.z, 0.0, 1e-6);
  EXPECT_EQ(sky.turbidity, 5.0f);
  EXPECT_EQ(sky.sunIntensity, 2.0f);
  EXPECT_EQ(sky.sunAngularRadiusDeg, 1.0f);
  EXPECT_EQ(sky.groundAlbedo, glm::vec3(0.5f));
  // Azimuth 0 looks to -Z, the equirect image centre.
  const SkyParameters front = parseSkySpec("elevation=0,azimuth=0");
  EXPECT_NEAR(front.sunDirection.z, -1.0, 1e-6);
}

TEST(Sky, BadSpecsAreRefused) {
  for (const char* spec : {"elevation=100", "turbidity=0.5", "sun=-1", "colour=3", "elevation",
                           "elevation=abc", "radius=0"}) {
    EXPECT_THROW(parseSkySpec(spec), Error) << spec;
  }
  try {
    parseSkySpec("colour=3");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("unknown key 'colour'", 0), 0u);
  }
  // Read as an environment source, the error names the source.
  try {
    loadEnvironment("sky:elevation=95");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "sky:elevation=95: elevation must be in [0, 90] degrees");
  }
}

TEST(Sky, SunIsTheBrightestTexelAndCarriesItsFlux) {
  SkyParameters params = parseSkySpec("elevation=40,azimuth=-60,turbidity=3");
  const Cubemap sky = makeSky(params, 32);
  const glm::vec3 sun = glm::normalize(params.sunDirection);
  int bf = 0, bx = 0, by = 0;
  float best = -1.0f;
  double sunFlux = 0.0, skyFlux = 0.0;
  forEachTexel(32, [&](int f, int x, int y) {
    const float lum = luminance(sky.at(f, x, y));
    ASSERT_TRUE(std::isfinite(lum));
    ASSERT_GE(lum, 0.0f);
    if (lum > best) best = lum, bf = f, bx = x, by = y;
    (glm::dot(sky.direction(f, x, y), sun) > 0.99f ? sunFlux : skyFlux) +=
        lum * sky.solidAngle(f, x, y);
  });
  EXPECT_GT(glm::dot(sky.direction(bf, bx, by), sun), 0.99f);
  // The sun gives 20 x the atmosphere's transmittance (0.6-0.8 at 40 degrees), the sky dome a
  // few units: a clear day.
  EXPECT_GT(sunFlux, 10.0);
  EXPECT_LT(sunFlux, 20.0);
  EXPECT_GT(skyFlux, 1.0);
  EXPECT_LT(skyFlux, sunFlux);
  // Below the horizon: uniform ground.
  EXPECT_EQ(sky.at(3, 3, 4), sky.at(3, 20, 9));
  // A large sun is drawn as a disc with the same flux.
  params.sunAngularRadiusDeg = 10.0f;
  const Cubemap big = makeSky(params, 64);
  double bigFlux = 0.0;
  forEachTexel(64, [&](int f, int x, int y) {
    if (glm::dot(big.direction(f, x, y), sun) > std::cos(0.25)) {
      bigFlux += luminance(big.at(f, x, y)) * big.solidAngle(f, x, y);
    }
  });
  EXPECT_GT(bigFlux, sunFlux);  // the disc plus the bright sky around it
  EXPECT_LT(bigFlux, sunFlux * 1.5);
}

}  // namespace
}  // namespace sss
