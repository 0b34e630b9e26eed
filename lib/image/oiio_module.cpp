// sss_oiio.so: OpenImageIO behind the interface of oiio_module.h. Built as a MODULE library
// (lib/image/CMakeLists.txt) from this file and image_limits.cpp only, so that loading it brings
// OpenImageIO and nothing of ours twice.
#include "image/oiio_module.h"

#include <algorithm>
#include <memory>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "core/error.h"
#include "image/image_limits.h"

namespace sss {
namespace {

DecodedImage read(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    std::string why = OIIO::geterror();
    if (why.empty()) why = "unknown format";
    fail(path, "cannot read image (" + why + ")");
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.depth > 1) {
    fail(path, "is a volume image (" + std::to_string(spec.width) + "x" +
                   std::to_string(spec.height) + "x" + std::to_string(spec.depth) +
                   "), not a picture");
  }
  if (spec.nchannels <= 0) fail(path, "image has no channels");
  // OpenImageIO opens a file whose header lies and fails only when reading the pixels.
  checkDeclaredImageSize(path, in->format_name(), spec.width, spec.height, spec.nchannels,
                         spec.format.basetype == OIIO::TypeDesc::FLOAT);
  // Only the channels used (RGB, or grey): a file may declare thousands.
  const int w = spec.width, h = spec.height, nch = std::min(spec.nchannels, 3);
  DecodedImage decoded;
  decoded.srgb = spec.format.basetype == OIIO::TypeDesc::UINT8 ||
                 spec.get_string_attribute("oiio:ColorSpace") == "sRGB";
  ImageRgb& image = decoded.image;
  image.width = w;
  image.height = h;
  image.pixels.resize(static_cast<std::size_t>(w) * h);
  // RGB straight into the pixels (glm::vec3 is three packed floats); grey through a buffer.
  static_assert(sizeof(glm::vec3) == 3 * sizeof(float));
  std::vector<float> grey(nch == 3 ? 0 : static_cast<std::size_t>(w) * h * nch);
  float* target = nch == 3 ? &image.pixels[0].x : grey.data();
  if (!in->read_image(0, 0, 0, nch, OIIO::TypeDesc::FLOAT, target)) {
    fail(path, "cannot read pixels (" + in->geterror() + ")");
  }
  in->close();
  if (nch < 3) {
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
      image.pixels[i] = glm::vec3(grey[i * nch]);
  }
  return decoded;
}

void write(const std::string& path, const PixelsToWrite& pixels) {
  auto out = OIIO::ImageOutput::create(path);
  if (!out) fail(path, "no image writer for this extension (" + OIIO::geterror() + ")");
  const bool linear = pixels.linear != nullptr;
  const OIIO::TypeDesc type = linear ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
  OIIO::ImageSpec spec(pixels.width, pixels.height, 3, type);
  for (const auto& [name, value] : pixels.attributes) spec.attribute(name, value);
  if (!linear) spec.attribute("oiio:ColorSpace", "sRGB");
  if (!out->open(path, spec)) fail(path, "cannot write (" + out->geterror() + ")");
  const void* data =
      linear ? static_cast<const void*>(pixels.linear) : static_cast<const void*>(pixels.srgb8);
  if (!out->write_image(type, data) || !out->close()) {
    fail(path, "cannot write (" + out->geterror() + ")");
  }
}

}  // namespace
}  // namespace sss

extern "C" const sss::OiioModule* sss_oiio_module() {
  static const sss::OiioModule module{sss::kOiioModuleAbi, sss::read, sss::write};
  return &module;
}
