// Pixels in memory, as the image readers return them and the writers take them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

namespace sss {

struct ImageRgb {
  int width = 0, height = 0;
  std::vector<glm::vec3> pixels;  // row-major, top row first
  glm::vec3& at(int x, int y) { return pixels[static_cast<std::size_t>(y) * width + x]; }
  const glm::vec3& at(int x, int y) const {
    return pixels[static_cast<std::size_t>(y) * width + x];
  }
};

// What a reader decoded: RGB (grey replicated, alpha dropped) and whether the values are
// sRGB-encoded (8-bit files), which readImage then linearises.
struct DecodedImage {
  ImageRgb image;
  bool srgb = false;
};

// Extra string attributes for a file's header, where the format allows.
using ImageAttributes = std::vector<std::pair<std::string, std::string>>;

// What a writer gets: RGB pixels, top row first, either linear floats (float formats) or sRGB
// bytes (8-bit formats), and the header's attributes.
struct PixelsToWrite {
  int width = 0, height = 0;
  const float* linear = nullptr;        // 3 floats a pixel, or null
  const std::uint8_t* srgb8 = nullptr;  // 3 bytes a pixel, or null
  ImageAttributes attributes;
  bool fastPng = false;  // zlib level 1 and no row filters
};

}  // namespace sss
