// PNG files through libpng (image_format.h decides when).
#pragma once

#include <string>

#include "image/image_rgb.h"

namespace sss {

// Any PNG (palette, grey, alpha, 1-16 bits) as RGB in [0, 1]: 8-bit and lower files and 16-bit
// ones without a linear gAMA chunk are sRGB-encoded (srgb = true). Throws Error naming the file
// for a bad file or a declared size over the limits (image_limits.h).
DecodedImage readPng(const std::string& path);

// 8-bit sRGB RGB with the chunks OpenImageIO 2.4 wrote for the same call, so the bytes match its
// files: sRGB with gAMA and cHRM, a zero oFFs, the attributes then "oiio:ColorSpace" = "sRGB" as
// tEXt; zlib level 6, its default strategy and libpng's adaptive filters, or level 1 and no
// filters for fastPng.
void writePng(const std::string& path, const PixelsToWrite& pixels);
// The same file's bytes in memory (a texture to embed); errors name `name`.
std::string encodePng(const std::string& name, const PixelsToWrite& pixels);

}  // namespace sss
