#include "envmap/environment.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "core/parallel.h"
#include "envmap/equirect.h"

namespace sss {
namespace {

// Face positions (column, row) in the horizontal cross, in face units; see environment.h.
constexpr int kCrossCol[6] = {2, 0, 1, 1, 1, 3};
constexpr int kCrossRow[6] = {1, 1, 0, 2, 1, 1};

// Bilinear lookup in an equirect image: u wraps, v clamps.
glm::vec3 sampleEquirect(const ImageRgb& image, float u, float v) {
  const float fx = u * image.width - 0.5f;
  const float fy = std::clamp(v * image.height - 0.5f, 0.0f, image.height - 1.0f);
  const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(fy);
  const float wx = fx - x0, wy = fy - y0;
  const int xa = (x0 % image.width + image.width) % image.width;
  const int xb = (xa + 1) % image.width;
  const int y1 = std::min(y0 + 1, image.height - 1);
  return (1 - wy) * ((1 - wx) * image.at(xa, y0) + wx * image.at(xb, y0)) +
         wy * ((1 - wx) * image.at(xa, y1) + wx * image.at(xb, y1));
}

Cubemap cubemapFromEquirect(const ImageRgb& image, int faceSize, int threads,
                            const EnvironmentOrientation& orientation) {
  const bool turned = !isIdentity(orientation, /*equirect=*/true);
  const glm::mat3 sourceFromWorldDir = sourceFromWorld(orientation, /*equirect=*/true);
  if (faceSize <= 0) faceSize = std::max(1, image.width / 4);
  Cubemap cube(faceSize);
  // Supersample so that the lookups are denser than the source texels (cube texel at a face
  // centre: 2 / N radians; equirect texel at the equator: 2 pi / W).
  const float ratio = image.width / (static_cast<float>(M_PI) * faceSize);
  const int k = std::max(2, static_cast<int>(std::ceil(1.5f * ratio)));
  parallelFor(
      6 * static_cast<std::size_t>(faceSize), threads, 4, [&](std::size_t begin, std::size_t end) {
        for (std::size_t row = begin; row < end; ++row) {
          const int f = static_cast<int>(row / faceSize), y = static_cast<int>(row % faceSize);
          for (int x = 0; x < faceSize; ++x) {
            cube.at(f, x, y) =
                Cubemap::averageOverTexel<glm::vec3>(f, x, y, faceSize, k, [&](glm::vec3 d) {
                  const glm::vec2 uv = equirectCoord(turned ? sourceFromWorldDir * d : d);
                  return sampleEquirect(image, uv.x, uv.y);
                });
          }
        }
      });
  return cube;
}

// A cube turned about +Y: each texel the mean of 2 x 2 bilinear lookups along the turned
// directions (a cube source has no exact analytic lookup to turn).
Cubemap turnedCubemap(const Cubemap& source, const glm::mat3& sourceFromWorldDir, int threads) {
  const int n = source.size();
  Cubemap cube(n);
  parallelFor(6 * static_cast<std::size_t>(n), threads, 4, [&](std::size_t begin, std::size_t end) {
    for (std::size_t row = begin; row < end; ++row) {
      const int f = static_cast<int>(row / n), y = static_cast<int>(row % n);
      for (int x = 0; x < n; ++x) {
        cube.at(f, x, y) = Cubemap::averageOverTexel<glm::vec3>(
            f, x, y, n, 2, [&](glm::vec3 d) { return source.sample(sourceFromWorldDir * d); });
      }
    }
  });
  return cube;
}

// Our stack, or a cross unfolded (see cubemapToCross), at the source resolution.
Cubemap cubeOrCrossToCubemap(const ImageRgb& image, EnvironmentLayout layout) {
  Cubemap cube;
  if (layout == EnvironmentLayout::CubemapStack) {
    const int n = image.width;
    cube = Cubemap(n);
    std::copy(image.pixels.begin(), image.pixels.end(), cube.data());
  } else if (image.width > image.height) {  // horizontal cross
    const int n = image.width / 4;
    cube = Cubemap(n);
    forEachTexel(n, [&](int f, int x, int y) {
      cube.at(f, x, y) = image.at(kCrossCol[f] * n + x, kCrossRow[f] * n + y);
    });
  } else {  // vertical cross: as the horizontal one, but -Z below -Y, turned by 180 degrees
    const int n = image.width / 3;
    cube = Cubemap(n);
    forEachTexel(n, [&](int f, int x, int y) {
      cube.at(f, x, y) = f == 5 ? image.at(2 * n - 1 - x, 4 * n - 1 - y)
                                : image.at(kCrossCol[f] * n + x, kCrossRow[f] * n + y);
    });
  }
  return cube;
}

}  // namespace

EnvironmentLayout detectLayout(const std::string& path, int width, int height) {
  if (width <= 0 || height <= 0) {
    fail(path,
         "image has zero size (" + std::to_string(width) + "x" + std::to_string(height) + ")");
  }
  if (width == 2 * height) return EnvironmentLayout::Equirect;
  if ((3 * width == 4 * height && width % 4 == 0) || (4 * width == 3 * height && width % 3 == 0)) {
    return EnvironmentLayout::Cross;
  }
  if (height == 6 * width) return EnvironmentLayout::CubemapStack;
  fail(path, "unsupported shape " + std::to_string(width) + "x" + std::to_string(height) +
                 ": expected 2:1 equirect, 4:3 or 3:4 cross, or an N x 6N cubemap stack");
}

Cubemap cubemapFromImage(const ImageRgb& image, EnvironmentLayout layout, int faceSize, int threads,
                         const EnvironmentOrientation& orientation) {
  if (layout == EnvironmentLayout::Equirect) {
    return cubemapFromEquirect(image, faceSize, threads, orientation);
  }
  Cubemap cube = cubeOrCrossToCubemap(image, layout);
  if (!isIdentity(orientation, /*equirect=*/false)) {
    cube = turnedCubemap(cube, sourceFromWorld(orientation, /*equirect=*/false), threads);
  }
  return faceSize > 0 && faceSize != cube.size() ? cube.resized(faceSize) : cube;
}

ImageRgb cubemapToCross(const Cubemap& cubemap) {
  const int n = cubemap.size();
  ImageRgb image;
  image.width = 4 * n;
  image.height = 3 * n;
  image.pixels.assign(static_cast<std::size_t>(image.width) * image.height, glm::vec3(0.0f));
  forEachTexel(n, [&](int f, int x, int y) {
    image.at(kCrossCol[f] * n + x, kCrossRow[f] * n + y) = cubemap.at(f, x, y);
  });
  return image;
}

ImageRgb cubemapToStack(const Cubemap& cubemap) {
  ImageRgb image;
  image.width = cubemap.size();
  image.height = 6 * cubemap.size();
  image.pixels.assign(cubemap.data(), cubemap.data() + cubemap.texelCount());
  return image;
}

void checkFaceSize(int faceSize) {
  if (faceSize < 1 || faceSize > kMaxFaceSize) {
    fail("", "a cubemap face size must be 1 to " + std::to_string(kMaxFaceSize) + " texels, got " +
                 std::to_string(faceSize));
  }
}

Cubemap loadEnvironment(const std::string& source, const EnvironmentOptions& options) {
  if (source == "sky" || source.rfind("sky:", 0) == 0) {
    SkyParameters sky;
    try {
      sky = parseSkySpec(source.size() > 4 ? source.substr(4) : "");
    } catch (const Error& e) {
      fail(source, e.what());
    }
    return makeSky(rotatedSky(sky, options.orientation),
                   options.faceSize > 0 ? options.faceSize : 128, options.threads);
  }
  const ImageRgb image = readImage(source, options.read);
  return cubemapFromImage(image, detectLayout(source, image.width, image.height), options.faceSize,
                          options.threads, options.orientation);
}

}  // namespace sss
