#include "envmap/cubemap_io.h"

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
  // OpenImageIO's EXR writer turns textureformat "CubeFace Environment" into OpenEXR's standard
  // envmap attribute (ENVMAP_CUBE): OpenEXR's cube layout stacks the faces vertically in our order.
  writeImage(
      path, cubemapToStack(cubemap),
      {{kCubemapLayoutAttribute, kCubemapLayoutTag}, {"textureformat", "CubeFace Environment"}});
}

std::string cubemapPreviewPath(const std::string& cubemapPath) {
  return std::filesystem::path(cubemapPath).replace_extension(".png").string();
}

void writeCubemapPreview(const std::string& path, const Cubemap& cubemap) {
  ImageRgb cross = cubemapToCross(cubemap.size() < 128 ? cubemap.resized(128) : cubemap);
  double logSum = 0.0;
  for (std::size_t i = 0; i < cubemap.texelCount(); ++i) {
    const glm::vec3 c = cubemap.data()[i];
    // Not core/luminance.h: the offset is added first, and summing in luminance()'s order would
    // round differently and change the preview's bytes.
    logSum += std::log(1e-6 + 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z);
  }
  const float scale = static_cast<float>(0.18 / std::exp(logSum / cubemap.texelCount()));
  for (glm::vec3& p : cross.pixels) p *= scale;
  writeImage(path, cross);
}

}  // namespace sss
