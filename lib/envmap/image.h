// A float RGB image in memory, and reading/writing it through OpenImageIO with every result
// checked (OIIO opens files whose header lies about the size and fails only on reading pixels).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "core/error.h"
#include "core/srgb.h"  // linearToSrgb / srgbToLinear for 8-bit images
#include "envmap/image_limits.h"

namespace sss {

struct ImageRgb {
  int width = 0, height = 0;
  std::vector<glm::vec3> pixels;  // row-major, top row first
  glm::vec3& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  const glm::vec3& at(int x, int y) const {
    return pixels[static_cast<std::size_t>(y) * width + x];
  }
};

// readImage's error for NaN/Inf texels without sanitize (a tool may name its flag for it).
class NonFiniteTexelsError : public Error {
 public:
  using Error::Error;
};

// What readImage does with non-finite and negative texels.
struct ImageReadOptions {
  bool sanitize = false;  // replace NaN/Inf by 0 (with a warning) instead of failing
  bool quiet = false;     // --quiet: no warnings about what was replaced or clamped
};

// The fewest bytes a file of OIIO format `format` ("hdr", "pnm", "openexr", ...) can hold a
// width x height image with `channels` channels in: Radiance HDR scanlines are flat (4 bytes a
// pixel) or run-length encoded (a 4-byte header, then at least 2 bytes per 127 pixels in each of
// 4 channels); PFM holds every float and other PNM at least a bit per sample; the formats that
// compress get a floor of 1 byte per 2^16 pixels (the most, DWAB-compressed EXR, was measured at
// 2,800 pixels a byte on a constant 4096 x 4096 image). Header bytes are not counted.
unsigned long long minimumImageFileBytes(const std::string& format, long long width,
                                         long long height, int channels, bool floatSamples);

// Reads any format OIIO knows (.hdr, .exr, .pfm, .tif, .png, ...) as linear float RGB (grey is
// replicated, alpha dropped). Throws Error naming the file for: missing/unreadable file, a
// directory, zero size, a header declaring more pixels than kMaxImagePixels or than the file's
// size holds, a volume (depth > 1), failed pixel read, NaN/Inf texels (NonFiniteTexelsError:
// count and first position) unless sanitize; negative texels are clamped to 0 with a warning.
ImageRgb readImage(const std::string& path, const ImageReadOptions& options = {});

// Writes through AtomicOutput: .exr/.hdr/.pfm as linear float, other extensions (.png, .jpg) as
// 8-bit sRGB after clamping. Extra string attributes go into the header where the format allows.
using ImageAttributes = std::vector<std::pair<std::string, std::string>>;
// fastPng: a .png with zlib level 1 and no row filters (previews: ~2x faster to write, larger).
void writeImage(const std::string& path, const ImageRgb& image,
                const ImageAttributes& attributes = {}, bool fastPng = false);

}  // namespace sss
