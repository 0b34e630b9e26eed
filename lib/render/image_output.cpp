#include "render/image_output.h"

#include <memory>

#include <OpenImageIO/imageio.h>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/file_extension.h"

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
  AtomicOutput out(path);
  auto writer = OIIO::ImageOutput::create(out.tempPath());
  if (!writer) fail(path, "no image writer for this extension (" + OIIO::geterror() + ")");
  const OIIO::TypeDesc type = image.linear ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
  OIIO::ImageSpec spec(image.width, image.height, 3, type);
  spec.attribute("Software", software);
  if (!image.linear) spec.attribute("oiio:ColorSpace", "sRGB");
  if (!writer->open(out.tempPath(), spec)) fail(path, "cannot write: " + writer->geterror());
  const void* data = image.linear ? static_cast<const void*>(image.linearRgb.data())
                                  : static_cast<const void*>(image.srgb8.data());
  if (!writer->write_image(type, data) || !writer->close()) {
    fail(path, "cannot write: " + writer->geterror());
  }
  out.commit();
}

}  // namespace sss
