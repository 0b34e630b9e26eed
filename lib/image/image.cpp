#include "image/image.h"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>

#include "core/atomic_output.h"
#include "core/file_extension.h"
#include "core/paths.h"
#include "core/tool.h"
#include "image/exr_file.h"
#include "image/image_format.h"
#include "image/oiio_file.h"
#include "image/png_file.h"
#include "image/rgbe_file.h"

namespace sss {
namespace {

// The backend image_format.h picks; a reader of our own may leave a variant to OpenImageIO.
DecodedImage decode(const std::string& path) {
  std::optional<DecodedImage> decoded;
  switch (readerFor(path)) {
    case ImageBackend::OpenExr:
      decoded = readExr(path);
      break;
    case ImageBackend::Png:
      decoded = readPng(path);
      break;
    case ImageBackend::RadianceHdr:
      decoded = readRgbe(path);
      break;
    case ImageBackend::OpenImageIO:
      break;
  }
  return decoded ? std::move(*decoded) : readWithOiio(path);
}

// NaN/Inf counted (first position kept) and zeroed, negatives clamped, sRGB values linearised.
void cleanTexels(const std::string& path, DecodedImage& decoded, const ImageReadOptions& options) {
  ImageRgb& image = decoded.image;
  std::size_t nonFinite = 0, negative = 0;
  int firstX = 0, firstY = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      glm::vec3& c = image.at(x, y);
      for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(c[k])) {
          if (nonFinite++ == 0) firstX = x, firstY = y;
          c[k] = 0.0f;
        } else if (c[k] < 0.0f) {
          ++negative;
          c[k] = 0.0f;
        } else if (decoded.srgb) {
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
}

}  // namespace

ImageRgb readImage(const std::string& path, const ImageReadOptions& options) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail(path, "no such file");
  checkInputFile(path);
  DecodedImage decoded = decode(path);
  cleanTexels(path, decoded, options);
  return std::move(decoded.image);
}

namespace {

void writeWith(ImageBackend backend, const std::string& path, const PixelsToWrite& pixels) {
  switch (backend) {
    case ImageBackend::OpenExr:
      writeExr(path, pixels);
      break;
    case ImageBackend::Png:
      writePng(path, pixels);
      break;
    case ImageBackend::RadianceHdr:
      writeRgbe(path, pixels);
      break;
    case ImageBackend::OpenImageIO:
      writeWithOiio(path, pixels);
      break;
  }
}

}  // namespace

void writeImagePixels(const std::string& path, const PixelsToWrite& pixels) {
  if (pixels.width <= 0 || pixels.height <= 0) fail(path, "refusing to write an empty image");
  AtomicOutput output(path);
  const std::string& temp = output.tempPath();
  const ImageBackend backend = writerFor(path);
  const bool needsLinear = backend == ImageBackend::OpenExr || backend == ImageBackend::RadianceHdr;
  if (backend != ImageBackend::OpenImageIO && needsLinear != (pixels.linear != nullptr)) {
    fail(path,
         needsLinear ? "this format holds linear float pixels" : "this format holds 8-bit pixels");
  }
  try {
    writeWith(backend, temp, pixels);
  } catch (const Error& e) {
    // The writers name the file they wrote, the temporary one; the user knows the other.
    const std::string message = e.what(), prefix = escapeControl(temp) + ": ";
    if (message.rfind(prefix, 0) != 0) throw;
    fail(path, message.substr(prefix.size()));
  }
  output.commit();
}

void writeImage(const std::string& path, const ImageRgb& image, const ImageAttributes& attributes,
                bool fastPng) {
  if (image.width <= 0 || image.height <= 0) fail(path, "refusing to write an empty image");
  PixelsToWrite pixels;
  pixels.width = image.width;
  pixels.height = image.height;
  pixels.attributes = attributes;
  pixels.fastPng = fastPng;
  std::vector<std::uint8_t> bytes;
  if (isFloatImageExtension(lowerExtension(path))) {
    pixels.linear = &image.pixels[0].x;
  } else {
    bytes.resize(image.pixels.size() * 3);
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
      for (int k = 0; k < 3; ++k) bytes[3 * i + k] = linearToSrgbByte(image.pixels[i][k]);
    }
    pixels.srgb8 = bytes.data();
  }
  writeImagePixels(path, pixels);
}

}  // namespace sss
