#include "render/image_output.h"

#include "core/error.h"
#include "core/file_extension.h"
#include "image/image.h"

namespace sss {

bool isLinearImagePath(const std::string& path) {
  const std::string ext = lowerExtension(path);
  return ext == "exr" || ext == "hdr" || ext == "pfm";
}

void checkRenderedImagePath(const std::string& path) {
  if (lowerExtension(path).empty()) {
    fail(path, "no file extension to choose the image format (.png or .exr)");
  }
}

void writeRenderedImage(const std::string& path, const RenderedImage& image,
                        const std::string& software) {
  checkRenderedImagePath(path);
  if (isLinearImagePath(path) != image.linear) {
    fail(path, image.linear ? "a linear image needs .exr, .hdr or .pfm"
                            : "an 8-bit image cannot go into a float format");
  }
  PixelsToWrite pixels;
  pixels.width = image.width;
  pixels.height = image.height;
  pixels.attributes = {{"Software", software}};
  if (image.linear) {
    pixels.linear = image.linearRgb.data();
  } else {
    pixels.srgb8 = image.srgb8.data();
  }
  writeImagePixels(path, pixels);
}

}  // namespace sss
