#include "envmap/cubemap_io.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>

#include "core/error.h"
#include "envmap/environment.h"

namespace sss {

Cubemap readCubemap(const std::string& path, const ImageReadOptions& options) {
  const ImageRgb image = readImage(path, options);
  if (image.height != 6 * image.width) {
    fail(path, "not a cubemap stack: " + std::to_string(image.width) + "x" +
                   std::to_string(image.height) + " (expected N x 6N)");
  }
  return cubemapFromImage(image, EnvironmentLayout::CubemapStack, 0);
}

void writeCubemap(const std::string& path, const Cubemap& cubemap) {
  if (cubemap.empty()) fail(path, "refusing to write an empty cubemap");
  // The EXR writer (image/exr_file.h) adds, for textureformat "CubeFace Environment", OpenEXR's
  // standard envmap attribute (ENVMAP_CUBE): OpenEXR's cube layout stacks the faces vertically in
  // our order.
  writeImage(
      path, cubemapToStack(cubemap),
      {{kCubemapLayoutAttribute, kCubemapLayoutTag}, {"textureformat", "CubeFace Environment"}});
}

std::string cubemapPreviewPath(const std::string& cubemapPath) {
  return std::filesystem::path(cubemapPath).replace_extension(".png").string();
}

namespace {

// Each face magnified m times by bilinear interpolation inside the face (edges clamped): for a
// picture only, so one lookup per pixel instead of resampling across the cube's seams.
Cubemap magnifiedFaces(const Cubemap& cube, int m) {
  const int n = cube.size(), size = n * m;
  Cubemap out(size);
  for (int f = 0; f < 6; ++f) {
    for (int y = 0; y < size; ++y) {
      const float fy = std::clamp((y + 0.5f) / m - 0.5f, 0.0f, n - 1.0f);
      const int y0 = std::min(static_cast<int>(fy), n - 1), y1 = std::min(y0 + 1, n - 1);
      const float wy = fy - y0;
      for (int x = 0; x < size; ++x) {
        const float fx = std::clamp((x + 0.5f) / m - 0.5f, 0.0f, n - 1.0f);
        const int x0 = std::min(static_cast<int>(fx), n - 1), x1 = std::min(x0 + 1, n - 1);
        const float wx = fx - x0;
        out.at(f, x, y) = (1 - wy) * ((1 - wx) * cube.at(f, x0, y0) + wx * cube.at(f, x1, y0)) +
                          wy * ((1 - wx) * cube.at(f, x0, y1) + wx * cube.at(f, x1, y1));
      }
    }
  }
  return out;
}

}  // namespace

void writeCubemapPreview(const std::string& path, const Cubemap& cubemap) {
  constexpr int kMinPreviewFace = 128;
  const int m = (kMinPreviewFace + cubemap.size() - 1) / cubemap.size();
  ImageRgb cross = cubemapToCross(m > 1 ? magnifiedFaces(cubemap, m) : cubemap);
  double logSum = 0.0;
  for (std::size_t i = 0; i < cubemap.texelCount(); ++i) {
    const glm::vec3 c = cubemap.data()[i];
    // Not core/luminance.h: the offset is added first, and summing in luminance()'s order would
    // round differently and change the preview's bytes.
    logSum += std::log(1e-6 + 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z);
  }
  const float scale = static_cast<float>(0.18 / std::exp(logSum / cubemap.texelCount()));
  for (glm::vec3& p : cross.pixels) p *= scale;
  writeImage(path, cross, {}, /*fastPng=*/true);
}

}  // namespace sss
