// Reading and writing images: one entry point for every format, with every result checked.
// image_format.h decides which backend handles which format: OpenEXR, libpng and our own
// Radiance HDR code for those three, OpenImageIO (loaded on first use) for the rest.
#pragma once

#include <string>

#include "core/error.h"
#include "core/srgb.h"  // linearToSrgb / srgbToLinear for 8-bit images
#include "image/image_limits.h"
#include "image/image_rgb.h"

namespace sss {

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

// Reads .exr, .hdr, .png and any format OpenImageIO knows (.pfm, .tif, ...) as linear float RGB
// (grey is replicated, alpha dropped). Throws Error naming the file for: missing/unreadable file,
// a directory, zero size, a header declaring more pixels than kMaxImagePixels or than the file's
// size holds, a volume (depth > 1), failed pixel read, NaN/Inf texels (NonFiniteTexelsError:
// count and first position) unless sanitize; negative texels are clamped to 0 with a warning.
ImageRgb readImage(const std::string& path, const ImageReadOptions& options = {});

// Writes through AtomicOutput: .exr/.hdr/.pfm/.tif as linear float, other extensions (.png,
// .jpg) as 8-bit sRGB after clamping. Extra string attributes go into the header where the
// format allows. fastPng: a .png with zlib level 1 and no row filters (previews: ~2x faster to
// write, larger).
void writeImage(const std::string& path, const ImageRgb& image,
                const ImageAttributes& attributes = {}, bool fastPng = false);

// Writes pixels as they are (linear floats or sRGB bytes, see PixelsToWrite) through
// AtomicOutput, with the backend image_format.h picks for the extension. Throws Error naming the
// file.
void writeImagePixels(const std::string& path, const PixelsToWrite& pixels);

// An 8-bit sRGB PNG (pixels.srgb8) encoded in memory, as writeImagePixels writes it to a .png: a
// texture to embed in another file. Errors name `name`.
std::string encodePng(const std::string& name, const PixelsToWrite& pixels);

}  // namespace sss
