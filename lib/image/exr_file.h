// OpenEXR files through the OpenEXR library itself (image_format.h decides when).
#pragma once

#include <optional>
#include <string>

#include "image/image_rgb.h"

namespace sss {

// The first part's data window as float RGB (R, G, B; or Y alone as grey), after
// checkExrHeader's walk; nullopt for channel layouts left to OpenImageIO (luminance-chroma,
// layers only, subsampled channels). Throws Error naming the file for a bad file.
std::optional<DecodedImage> readExr(const std::string& path);

// Float RGB, ZIP-compressed, scanlines, with the header OpenImageIO 2.4 wrote for the same call,
// so the bytes match its files but for capDate (the time of writing): capDate, the attributes as
// strings, and OpenEXR's envmap = ENVMAP_CUBE where textureformat is "CubeFace Environment".
void writeExr(const std::string& path, const PixelsToWrite& pixels);

}  // namespace sss
