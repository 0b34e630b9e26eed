// Reading and writing cubemaps in the project's file layout: one float RGB EXR of N x 6N pixels,
// the six faces stacked vertically (+X, -X, +Y, -Y, +Z, -Z), each in OpenGL orientation, row 0 at
// the top. The header carries the attribute "sss:layout" = kCubemapLayoutTag so that tools can
// tell our stack from an arbitrary 1:6 image (readCubemap accepts both; the tag is informative),
// and OpenEXR's standard "envmap" attribute = ENVMAP_CUBE (1), which other EXR tools read.
#pragma once

#include <string>

#include "envmap/cubemap.h"
#include "image/image.h"

namespace sss {

inline constexpr const char* kCubemapLayoutAttribute = "sss:layout";
inline constexpr const char* kCubemapLayoutTag = "cubemap-stack +X -X +Y -Y +Z -Z (OpenGL, Y up)";

// Throws Error naming the file for unreadable files, a shape other than N x 6N, or bad texels
// (see readImage).
Cubemap readCubemap(const std::string& path, const ImageReadOptions& options = {});
// Writes through AtomicOutput (the file appears whole or not at all).
void writeCubemap(const std::string& path, const Cubemap& cubemap);

// The preview beside a cubemap file: FILE.exr -> FILE.png.
std::string cubemapPreviewPath(const std::string& cubemapPath);
// An 8-bit sRGB image of the unfolded cross (cubemapToCross; faces of at least 128 pixels, small
// cubemaps magnified an integer number of times, bilinearly within each face), exposed so that
// the log-average luminance maps to 0.18 (Reinhard et al. 2002's key value), clamped.
void writeCubemapPreview(const std::string& path, const Cubemap& cubemap);

}  // namespace sss
