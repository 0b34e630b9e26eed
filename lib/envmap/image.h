// A float RGB image in memory, and reading/writing it through OpenImageIO with every result
// checked (OIIO opens files whose header lies about the size and fails only on reading pixels).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "core/error.h"
#include "core/srgb.h"  // linearToSrgb / srgbToLinear for 8-bit images

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
};

// Reads any format OIIO knows (.hdr, .exr, .pfm, .tif, .png, ...) as linear float RGB (grey is
// replicated, alpha dropped). Throws Error naming the file for: missing/unreadable file, zero
// size, failed pixel read, NaN/Inf texels (NonFiniteTexelsError: count and first position) unless
// sanitize; negative
// texels are clamped to 0 with a warning.
ImageRgb readImage(const std::string& path, const ImageReadOptions& options = {});

// Writes through AtomicOutput: .exr/.hdr/.pfm as linear float, other extensions (.png, .jpg) as
// 8-bit sRGB after clamping. Extra string attributes go into the header where the format allows.
using ImageAttributes = std::vector<std::pair<std::string, std::string>>;
void writeImage(const std::string& path, const ImageRgb& image,
                const ImageAttributes& attributes = {});

}  // namespace sss
