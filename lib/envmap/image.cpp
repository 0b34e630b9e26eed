#include "envmap/image.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>

#include <OpenImageIO/imageio.h>

#include "core/atomic_output.h"
#include "core/error.h"
#include "core/file_extension.h"
#include "core/paths.h"
#include "core/tool.h"
#include "envmap/exr_header.h"

namespace sss {

namespace {

// The header's size against kMaxImagePixels and the file's size, before the pixels are
// allocated (OIIO opens a file whose header lies and fails only when reading the pixels).
void checkDeclaredSize(const std::string& path, const OIIO::ImageInput& in) {
  const OIIO::ImageSpec& spec = in.spec();
  const std::string size = std::to_string(spec.width) + "x" + std::to_string(spec.height);
  if (spec.depth > 1) {
    fail(path,
         "is a volume image (" + size + "x" + std::to_string(spec.depth) + "), not a picture");
  }
  const long long pixels = static_cast<long long>(spec.width) * spec.height;
  if (pixels > kMaxImagePixels) {
    fail(path, "header declares " + size + " pixels, more than the " +
                   std::to_string(kMaxImagePixels) + " (2^28) an image may have");
  }
  std::error_code ec;
  const unsigned long long bytes = std::filesystem::file_size(path, ec);
  const unsigned long long needed =
      minimumImageFileBytes(in.format_name(), spec.width, spec.height, spec.nchannels,
                            spec.format.basetype == OIIO::TypeDesc::FLOAT);
  if (!ec && bytes < needed) {
    fail(path, "header declares " + size + " pixels, which take at least " +
                   std::to_string(needed) + " bytes, but the file has " + std::to_string(bytes) +
                   " (truncated?)");
  }
}

}  // namespace

unsigned long long minimumImageFileBytes(const std::string& format, long long width,
                                         long long height, int channels, bool floatSamples) {
  const unsigned long long w = static_cast<unsigned long long>(std::max(width, 0LL));
  const unsigned long long h = static_cast<unsigned long long>(std::max(height, 0LL));
  const unsigned long long c = static_cast<unsigned long long>(std::max(channels, 0));
  if (format == "hdr") {
    // Widths outside [8, 32767] cannot be run-length encoded.
    const unsigned long long row = w < 8 || w > 32767 ? 4 * w : 4 + 8 * ((w + 126) / 127);
    return h * row;
  }
  if (format == "pnm") return floatSamples ? w * h * c * 4 : w * h * c / 8;
  return w * h / 65536;
}

ImageRgb readImage(const std::string& path, const ImageReadOptions& options) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail(path, "no such file");
  checkInputFile(path);
  checkExrHeader(path);  // by content: OIIO tries its EXR reader on any file the others refuse
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    std::string why = OIIO::geterror();
    if (why.empty()) why = "unknown format";
    fail(path, "cannot read image (" + why + ")");
  }
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
    fail(path, "image has zero size (" + std::to_string(spec.width) + "x" +
                   std::to_string(spec.height) + ")");
  }
  checkDeclaredSize(path, *in);
  // Only the channels used (RGB, or grey): an EXR may declare thousands.
  const int w = spec.width, h = spec.height, nch = std::min(spec.nchannels, 3);
  const bool srgb = spec.format.basetype == OIIO::TypeDesc::UINT8 ||
                    spec.get_string_attribute("oiio:ColorSpace") == "sRGB";
  ImageRgb image;
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

  std::size_t nonFinite = 0, negative = 0;
  int firstX = 0, firstY = 0;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      glm::vec3& c = image.at(x, y);
      if (nch < 3) c = glm::vec3(grey[(static_cast<std::size_t>(y) * w + x) * nch]);
      for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(c[k])) {
          if (nonFinite++ == 0) firstX = x, firstY = y;
          c[k] = 0.0f;
        } else if (c[k] < 0.0f) {
          ++negative;
          c[k] = 0.0f;
        } else if (srgb) {
          c[k] = srgbToLinear(c[k]);
        }
      }
    }
  }
  if (nonFinite > 0) {
    const std::string what = std::to_string(nonFinite) + " NaN/Inf texel values, first at (" +
                             std::to_string(firstX) + ", " + std::to_string(firstY) + ")";
    if (!options.sanitize) throw NonFiniteTexelsError(path + ": " + what);
    if (!options.quiet) warn(path + ": " + what + " replaced by 0");
  }
  if (negative > 0 && !options.quiet) {
    warn(path + ": " + std::to_string(negative) + " negative texel values clamped to 0");
  }
  return image;
}

void writeImage(const std::string& path, const ImageRgb& image, const ImageAttributes& attributes,
                bool fastPng) {
  if (image.width <= 0 || image.height <= 0) fail(path, "refusing to write an empty image");
  const std::string ext = lowerExtension(path);
  const bool isFloat =
      ext == "exr" || ext == "hdr" || ext == "pfm" || ext == "tif" || ext == "tiff";
  AtomicOutput output(path);
  auto out = OIIO::ImageOutput::create(output.tempPath());
  if (!out) fail(path, "no image writer for this extension (" + OIIO::geterror() + ")");
  OIIO::ImageSpec spec(image.width, image.height, 3,
                       isFloat ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  for (const auto& [name, value] : attributes) spec.attribute(name, value);
  if (!isFloat) spec.attribute("oiio:ColorSpace", "sRGB");
  if (fastPng) {
    spec.attribute("png:compressionLevel", 1);
    spec.attribute("png:filter", 8);  // PNG_FILTER_NONE
  }
  if (!out->open(output.tempPath(), spec)) fail(path, "cannot write (" + out->geterror() + ")");
  bool ok;
  if (isFloat) {
    ok = out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data());
  } else {
    std::vector<std::uint8_t> bytes(image.pixels.size() * 3);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        bytes[3 * i + k] = linearToSrgbByte(image.pixels[i][k]);
      }
    }
    ok = out->write_image(OIIO::TypeDesc::UINT8, bytes.data());
  }
  if (!ok || !out->close()) fail(path, "cannot write (" + out->geterror() + ")");
  out.reset();
  output.commit();
}

}  // namespace sss
