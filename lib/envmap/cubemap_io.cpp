#include "envmap/cubemap_io.h"

#include <cstring>

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
  writeImage(path, cubemapToStack(cubemap), {{kCubemapLayoutAttribute, kCubemapLayoutTag}});
}

}  // namespace sss
