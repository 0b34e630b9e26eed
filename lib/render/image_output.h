// Writing rendered images: 8-bit sRGB (.png, .jpg, .tif, ...) or linear float (.exr, .hdr,
// .pfm), whole or not at all (AtomicOutput).
#pragma once

#include <string>

#include "render/renderer.h"

namespace sss {

// True for the float formats (.exr, .hdr, .pfm), which get linear values.
bool isLinearImagePath(const std::string& path);
// Throws Error naming the file when it has no extension to choose the image format from.
void checkRenderedImagePath(const std::string& path);

// Writes the image (RGB, top row first) through lib/image; throws Error naming the file.
// `software` is recorded in the file's metadata where the format allows.
void writeRenderedImage(const std::string& path, const RenderedImage& image,
                        const std::string& software = "sss-render");

}  // namespace sss
