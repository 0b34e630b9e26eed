// Radiance HDR (RGBE) files: a reader and writer of our own (image_format.h decides when).
#pragma once

#include <optional>
#include <string>

#include "image/image_rgb.h"

namespace sss {

// A "-Y H +X W" RGBE picture, flat or run-length encoded; nullopt for what it leaves to
// OpenImageIO (other orientations, XYZE pixels). Throws Error naming the file for a bad header,
// a declared size over the limits (image_limits.h) or a truncated or corrupt scanline.
std::optional<DecodedImage> readRgbe(const std::string& path);

// Run-length encoded RGBE (Walter's rgbe.c encoding) of the linear pixels.
void writeRgbe(const std::string& path, const PixelsToWrite& pixels);

}  // namespace sss
