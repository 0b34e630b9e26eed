// Radiance HDR (RGBE) files: a reader and writer of our own (image_format.h decides when).
#pragma once

#include <optional>
#include <string>

#include "image/image_rgb.h"

namespace sss {

// An RGBE picture, flat or run-length encoded, in any of the four unrotated orientations ("-Y H
// +X W" the usual one; "+Y" bottom row first, "-X" rows right to left); nullopt for a rotated
// one ("+X W -Y H", ...), which OpenImageIO reads. Throws Error naming the file for a bad header,
// a pixel format other than RGBE, a declared size over the limits (image_limits.h) or a
// truncated or corrupt scanline.
std::optional<DecodedImage> readRgbe(const std::string& path);

// Run-length encoded RGBE (Walter's rgbe.c encoding) of the linear pixels.
void writeRgbe(const std::string& path, const PixelsToWrite& pixels);

}  // namespace sss
