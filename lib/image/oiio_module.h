// The boundary between the tools and OpenImageIO: a module of ours (sss_oiio.so, a CMake MODULE
// library linking OpenImageIO, installed beside the tools) that oiio_file.cpp loads with dlopen
// the first time a file needs it. Both sides are built together with the same compiler and
// standard library, so the entry point hands C++ types over, and an Error thrown in the module
// reaches the caller's handlers.
#pragma once

#include <string>

#include "image/image_rgb.h"

namespace sss {

// Raised when a header, an interface or its behaviour changes: a module from another build is
// refused instead of misread.
inline constexpr int kOiioModuleAbi = 1;
inline constexpr const char* kOiioModuleFile = "sss_oiio.so";
inline constexpr const char* kOiioModuleEntry = "sss_oiio_module";

struct OiioModule {
  int abi = kOiioModuleAbi;
  // The first subimage as RGB (grey replicated, alpha dropped): the checks of readImage's
  // contract (zero size, volumes, declared size against the limits and the file's size) before
  // the pixels are allocated. Throws Error naming the file.
  DecodedImage (*read)(const std::string& path) = nullptr;
  // Float RGB (pixels.linear) or 8-bit sRGB RGB (pixels.srgb8), the format from path's
  // extension. Throws Error naming the file.
  void (*write)(const std::string& path, const PixelsToWrite& pixels) = nullptr;
};

}  // namespace sss

// The module's one exported symbol.
extern "C" const sss::OiioModule* sss_oiio_module();
