// The compact lights split off an environment (envmap/compact_lights.h): a sun over a sky is found
// where it is, with its flux; the flux is conserved; an even sky has none.
#include <cmath>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "core/luminance.h"
#include "envmap/compact_lights.h"

namespace sss {
namespace {

// Sum of L dw per channel over the map.
glm::dvec3 flux(const Cubemap& map) {
  glm::dvec3 sum(0.0);
  forEachTexel(map.size(), [&](int f, int x, int y) {
    sum += glm::dvec3(map.at(f, x, y)) * double(map.solidAngle(f, x, y));
  });
  return sum;
}

Cubemap skyWithSun(const glm::vec3& sun, float radiusDeg, int size) {
  Cubemap map(size, glm::vec3(0.2f, 0.3f, 0.5f));
  const float cosRadius = std::cos(radiusDeg * float(M_PI) / 180.0f);
  forEachTexel(size, [&](int f, int x, int y) {
    if (glm::dot(map.direction(f, x, y), sun) >= cosRadius) map.at(f, x, y) = glm::vec3(5e4f);
  });
  return map;
}

TEST(CompactLights, FindsTheSunWithItsFlux) {
  const glm::vec3 sun = glm::normalize(glm::vec3(0.3f, 0.8f, -0.5f));
  const Cubemap map = skyWithSun(sun, 1.0f, 128);
  const CompactLightSplit split = splitCompactLights(map);
  ASSERT_EQ(split.lights.size(), 1u);
  EXPECT_GT(glm::dot(split.lights[0].direction, sun), std::cos(0.5 * M_PI / 180.0));
  // The sun's texels: everything above the sky's radiance.
  const glm::dvec3 sunFlux = flux(map) - flux(Cubemap(128, glm::vec3(0.2f, 0.3f, 0.5f)));
  const glm::dvec3 found = glm::dvec3(split.lights[0].irradiance);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(found[c], sunFlux[c], 1e-3 * sunFlux[c]) << c;
  EXPECT_GT(split.fluxShare, 0.5);
  // Lights and rest add up to the map.
  const glm::dvec3 total = flux(split.rest) + found;
  const glm::dvec3 all = flux(map);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(total[c], all[c], 1e-5 * all[c]) << c;
}

TEST(CompactLights, TwoLampsAreTwoLights) {
  Cubemap map = skyWithSun(glm::vec3(0.0f, 1.0f, 0.0f), 1.5f, 128);
  const Cubemap second = skyWithSun(glm::vec3(1.0f, 0.0f, 0.0f), 1.5f, 128);
  forEachTexel(128, [&](int f, int x, int y) {
    map.at(f, x, y) = glm::max(map.at(f, x, y), second.at(f, x, y));
  });
  const CompactLightSplit split = splitCompactLights(map);
  ASSERT_EQ(split.lights.size(), 2u);
  EXPECT_NEAR(luminance(split.lights[0].irradiance), luminance(split.lights[1].irradiance),
              0.1 * luminance(split.lights[0].irradiance));
}

TEST(CompactLights, AnEvenSkyHasNone) {
  Cubemap map(64, glm::vec3(1.0f));
  forEachTexel(
      64, [&](int f, int x, int y) { map.at(f, x, y) *= 1.0f + 0.5f * map.direction(f, x, y).z; });
  const CompactLightSplit split = splitCompactLights(map);
  EXPECT_TRUE(split.lights.empty());
  EXPECT_EQ(split.fluxShare, 0.0);
}

}  // namespace
}  // namespace sss
