// Every image format without a reader of our own, through OpenImageIO (oiio_module.h), loaded
// the first time one is read or written.
#pragma once

#include <string>

#include "image/image_rgb.h"

namespace sss {

// Throws Error naming the file, also when the module cannot be found or loaded.
DecodedImage readWithOiio(const std::string& path);
void writeWithOiio(const std::string& path, const PixelsToWrite& pixels);

// Whether this process has loaded OpenImageIO (for the tests of what a run loads).
bool oiioLoaded();

}  // namespace sss
