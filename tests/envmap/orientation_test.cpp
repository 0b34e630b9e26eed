// --env-convention and --env-rotate (envmap/orientation.h): a bright spot painted at a known
// pixel lands where each application shows it (their mappings written here from their sources,
// independently of ours), rotations turn equirect, cube and sky sources alike, and the cubemap EXR
// carries OpenEXR's envmap attribute.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "envmap/cubemap_io.h"
#include "envmap/environment.h"
#include "envmap/equirect.h"
#include "envmap/orientation.h"
#include "expect_near.h"
#include "support/tool_test.h"

namespace sss {
namespace {

using test::expectNear;
constexpr float kPi = static_cast<float>(M_PI);

// Blender/Cycles (intern/cycles/kernel/camera/projection.h: equirectangular_to_direction, range
// (-2 pi, pi, -pi, pi), spherical_to_direction), Z-up, image v = 0 at the bottom; then Blender's
// axes to glTF's Y-up ones as Blender's glTF exporter maps them: (x, y, z) -> (x, z, -y).
glm::vec3 blenderShows(float u, float vTop) {
  const float vBottom = 1.0f - vTop;
  const float phi = -2.0f * kPi * u + kPi, theta = -kPi * vBottom + kPi;
  const glm::vec3 zUp(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                      std::cos(theta));
  return {zUp.x, zUp.z, -zUp.y};
}

// three.js equirectUv (ShaderChunk/common.glsl.js): u = atan(z, x) / 2 pi + 0.5,
// v = asin(y) / pi + 0.5, with textures flipped so that v = 1 is the image's top row. Inverted.
glm::vec3 threejsShows(float u, float vTop) {
  const float phi = 2.0f * kPi * (u - 0.5f), lat = kPi * ((1.0f - vTop) - 0.5f);
  return {std::cos(lat) * std::cos(phi), std::sin(lat), std::cos(lat) * std::sin(phi)};
}

// Filament's cmgen: equirectangularToCubemap maps direction s to x = (atan2(s.x, s.z) / pi + 1)
// / 2, y = (1 - asin(s.y) 2 / pi) / 2 (inverted here), then mirrorCubemap (on by default) shows
// at N what was at (-N.x, N.y, N.z).
glm::vec3 filamentShows(float u, float vTop) {
  const float lambda = kPi * (2.0f * u - 1.0f), lat = 0.5f * kPi * (1.0f - 2.0f * vTop);
  const glm::vec3 s(std::cos(lat) * std::sin(lambda), std::sin(lat),
                    std::cos(lat) * std::cos(lambda));
  return {-s.x, s.y, s.z};
}

// A dim equirect with a 3 x 3 pixel bright spot centred on pixel (px, py).
ImageRgb spotImage(int width, int px, int py) {
  ImageRgb image;
  image.width = width;
  image.height = width / 2;
  image.pixels.assign(static_cast<std::size_t>(image.width) * image.height, glm::vec3(0.01f));
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) image.at(px + dx, py + dy) = glm::vec3(1000.0f);
  }
  return image;
}

// Where the bright texels are: their flux-weighted mean direction.
glm::vec3 brightDirection(const Cubemap& cube) {
  glm::vec3 sum(0.0f);
  forEachTexel(cube.size(), [&](int f, int x, int y) {
    const float value = cube.at(f, x, y).x;
    if (value > 1.0f) sum += value * cube.solidAngle(f, x, y) * cube.direction(f, x, y);
  });
  return glm::normalize(sum);
}

float angleDeg(const glm::vec3& a, const glm::vec3& b) {
  return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0f, 1.0f)) *
         180.0f / kPi;
}

constexpr int kWidth = 512, kSpotX = 307, kSpotY = 90;  // u = 0.6006, v = 0.3535
constexpr float kU = (kSpotX + 0.5f) / kWidth, kV = (kSpotY + 0.5f) / (kWidth / 2);

glm::vec3 spotLandsAt(const EnvironmentOrientation& orientation) {
  return brightDirection(cubemapFromImage(spotImage(kWidth, kSpotX, kSpotY),
                                          EnvironmentLayout::Equirect, 64, 0, orientation));
}

TEST(EnvConvention, BrightSpotLandsWhereEachApplicationShowsIt) {
  const struct {
    EquirectConvention convention;
    glm::vec3 shown;
  } cases[] = {{EquirectConvention::Sss, equirectDirection(kU, kV)},
               {EquirectConvention::Blender, blenderShows(kU, kV)},
               {EquirectConvention::Threejs, threejsShows(kU, kV)},
               {EquirectConvention::Filament, filamentShows(kU, kV)}};
  for (const auto& c : cases) {
    const glm::vec3 landed = spotLandsAt({c.convention, 0.0});
    EXPECT_LT(angleDeg(landed, c.shown), 1.0f)
        << kEquirectConventionNames.name(c.convention) << ": landed at " << landed.x << ","
        << landed.y << "," << landed.z;
  }
  // The conventions do differ: the spot of one is far from where another shows it.
  EXPECT_GT(angleDeg(blenderShows(kU, kV), equirectDirection(kU, kV)), 45.0f);
  EXPECT_GT(angleDeg(filamentShows(kU, kV), equirectDirection(kU, kV)), 45.0f);
  EXPECT_LT(angleDeg(blenderShows(kU, kV), threejsShows(kU, kV)), 0.01f);
}

TEST(EnvConvention, ImageCentresLookWhereTheREADMESays) {
  expectNear(blenderShows(0.5f, 0.5f), {1, 0, 0}, 1e-5f);
  expectNear(blenderShows(0.75f, 0.5f), {0, 0, 1}, 1e-5f);
  expectNear(threejsShows(0.5f, 0.5f), {1, 0, 0}, 1e-5f);
  expectNear(filamentShows(0.5f, 0.5f), {0, 0, 1}, 1e-5f);
  expectNear(filamentShows(0.75f, 0.5f), {-1, 0, 0}, 1e-5f);
  expectNear(blenderShows(0.3f, 0.0f), {0, 1, 0}, 1e-5f);  // every top row is up
  expectNear(threejsShows(0.3f, 0.0f), {0, 1, 0}, 1e-5f);
  expectNear(filamentShows(0.3f, 0.0f), {0, 1, 0}, 1e-5f);
}

TEST(EnvRotate, TurnsCounterClockwiseSeenFromAbove) {
  expectNear(rotationAboutY(90.0) * glm::vec3(0, 0, -1), {-1, 0, 0}, 0.0f);  // exact
  expectNear(rotationAboutY(90.0) * glm::vec3(1, 0, 0), {0, 0, -1}, 0.0f);
  expectNear(rotationAboutY(-450.0) * glm::vec3(1, 0, 0), {0, 0, 1}, 0.0f);
  const glm::vec3 d = glm::normalize(glm::vec3(0.3f, 0.5f, -0.8f));
  expectNear(rotationAboutY(30.0) * (rotationAboutY(-30.0) * d), d, 1e-6f);
}

TEST(EnvRotate, SpotTurnsWithTheEnvironmentInEveryConvention) {
  for (const double deg : {90.0, -37.0, 180.0}) {
    for (const EquirectConvention c : {EquirectConvention::Sss, EquirectConvention::Blender}) {
      const glm::vec3 unturned = spotLandsAt({c, 0.0});
      const glm::vec3 expected = rotationAboutY(deg) * unturned;
      EXPECT_LT(angleDeg(spotLandsAt({c, deg}), expected), 1.0f) << deg;
    }
  }
}

TEST(EnvRotate, IdentityLeavesTheCubemapBitExact) {
  const ImageRgb image = spotImage(256, 100, 40);
  const Cubemap plain = cubemapFromImage(image, EnvironmentLayout::Equirect, 32);
  const Cubemap full =
      cubemapFromImage(image, EnvironmentLayout::Equirect, 32, 0, {EquirectConvention::Sss, 360.0});
  ASSERT_EQ(plain.texelCount(), full.texelCount());
  EXPECT_EQ(std::memcmp(plain.data(), full.data(), plain.texelCount() * sizeof(glm::vec3)), 0);
}

// A smooth environment: +X red, +Y green, +Z blue and dimmer mixes for the negative axes.
glm::vec3 axisColour(const glm::vec3& d) {
  const glm::vec3 n = glm::max(-d, glm::vec3(0.0f));
  return glm::max(d, glm::vec3(0.0f)) + 0.25f * glm::vec3(n.z, n.x, n.y);
}

TEST(EnvRotate, CrossSourceTurnsLikeTheEquirect) {
  ImageRgb equirect;
  equirect.width = 512;
  equirect.height = 256;
  for (int y = 0; y < 256; ++y) {
    for (int x = 0; x < 512; ++x) {
      equirect.pixels.push_back(axisColour(equirectDirection((x + 0.5f) / 512, (y + 0.5f) / 256)));
    }
  }
  const Cubemap cube = cubemapFromImage(equirect, EnvironmentLayout::Equirect, 32);
  const EnvironmentOrientation turn{EquirectConvention::Sss, 60.0};
  const Cubemap fromCross =
      cubemapFromImage(cubemapToCross(cube), EnvironmentLayout::Cross, 0, 0, turn);
  float worst = 0.0f;
  for (int f = 0; f < 6; ++f) {
    for (int y = 0; y < 32; y += 3) {
      for (int x = 0; x < 32; x += 3) {
        // The turned environment shows along w what the source showed along R_y(-60) w.
        const glm::vec3 w = cube.direction(f, x, y);
        const glm::vec3 expected = axisColour(rotationAboutY(-60.0) * w);
        worst = std::max(worst, glm::length(fromCross.at(f, x, y) - expected));
      }
    }
  }
  EXPECT_LT(worst, 0.05f);
}

TEST(EnvRotate, SkySunTurnsWithTheSky) {
  const SkyParameters sky = parseSkySpec("elevation=30,azimuth=20");
  // Azimuth runs from -Z towards +X (clockwise seen from above): a counter-clockwise turn by 90
  // degrees takes azimuth 20 to -70.
  expectNear(rotatedSky(sky, {EquirectConvention::Sss, 90.0}).sunDirection,
             parseSkySpec("elevation=30,azimuth=-70").sunDirection, 1e-6f);
  // The convention is for equirect images only.
  expectNear(rotatedSky(sky, {EquirectConvention::Blender, 0.0}).sunDirection, sky.sunDirection,
             0.0f);
  // The whole sky turns: loading "sky:" with a turn equals the turned spec.
  EnvironmentOptions options;
  options.faceSize = 16;
  options.orientation.rotateDeg = 90.0;
  const Cubemap turned = loadEnvironment("sky:elevation=30,azimuth=20", options);
  const Cubemap expected = makeSky(parseSkySpec("elevation=30,azimuth=-70"), 16);
  float worst = 0.0f, peak = 0.0f;
  for (std::size_t i = 0; i < turned.texelCount(); ++i) {
    worst = std::max(worst, glm::length(turned.data()[i] - expected.data()[i]));
    peak = std::max(peak, glm::length(expected.data()[i]));
  }
  EXPECT_LT(worst, 1e-4f * peak);
}

// OpenEXR's header: after the magic number and version, attributes as name\0 type\0 int32 size
// and the value; "envmap" has type "envmap", size 1, value 1 for ENVMAP_CUBE.
TEST(CubemapFile, CarriesOpenExrsEnvmapCubeAttribute) {
  test::ScratchDir scratch;
  const std::string path = scratch.path("cube.exr");
  writeCubemap(path, Cubemap(4, glm::vec3(0.5f)));
  std::ifstream in(path, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  const std::string key("envmap\0envmap\0", 14);
  const std::size_t at = bytes.find(key);
  ASSERT_NE(at, std::string::npos) << "no envmap attribute in the header";
  std::int32_t size = 0;
  std::memcpy(&size, bytes.data() + at + key.size(), 4);
  EXPECT_EQ(size, 1);
  EXPECT_EQ(static_cast<unsigned char>(bytes[at + key.size() + 4]), 1u);  // ENVMAP_CUBE
  EXPECT_NE(bytes.find(std::string(kCubemapLayoutAttribute) + '\0'), std::string::npos);
  // Still one level, read back as before.
  const Cubemap back = readCubemap(path);
  EXPECT_EQ(back.size(), 4);
  expectNear(back.at(3, 1, 2), glm::vec3(0.5f), 0.0f);
}

}  // namespace
}  // namespace sss
