#include "image/rgbe_file.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

#include <glm/common.hpp>

#include "core/error.h"
#include "image/image_limits.h"

namespace sss {
namespace {

// The format (Ward, "The RADIANCE Picture File Format", radsite.lbl.gov/radiance/refer/
// filefmts.pdf): "#?" and a program name, header lines up to an empty line (FORMAT= names the
// pixel encoding), a resolution line, then the scanlines. A scanline of 8 to 32767 pixels may be
// run-length encoded ("new" RLE): the bytes 2, 2, width >> 8, width & 255, then each of the four
// components in turn as runs (a count byte above 128: count - 128 copies of the next byte) and
// literal dumps (a count byte up to 128: that many bytes). Any other scanline is flat, 4 bytes a
// pixel.
constexpr int kMinRunLengthWidth = 8, kMaxRunLengthWidth = 32767;

struct Header {
  long long width = 0, height = 0;
  // "-Y H +X W" is rows top to bottom, columns left to right; "+Y" stores the bottom row first,
  // "-X" each row right to left. "+X W -Y H" and the like (columns stored first) are rotated.
  bool bottomUp = false, rightToLeft = false, rotated = false;
};

// The header lines and the resolution line; `pos` is left at the first scanline byte.
Header readHeader(const std::string& path, const std::string& bytes, std::size_t& pos) {
  Header header;
  auto line = [&]() {
    const std::size_t end = bytes.find('\n', pos);
    if (end == std::string::npos) fail(path, "Radiance HDR header is not terminated");
    std::string text = bytes.substr(pos, end - pos);
    pos = end + 1;
    return text;
  };
  line();  // "#?RADIANCE", "#?RGBE", ...
  for (std::string text = line(); !text.empty(); text = line()) {
    if (text.rfind("FORMAT=", 0) == 0 && text != "FORMAT=32-bit_rle_rgbe") {
      // XYZE too: OpenImageIO 2.4 refuses it as well.
      fail(path, "Radiance HDR pixel format '" + text.substr(7, 40) +
                     "' is not supported (only 32-bit_rle_rgbe)");
    }
  }
  const std::string resolution = line();
  std::istringstream fields(resolution);
  std::string yAxis, height, xAxis, width;
  fields >> yAxis >> height >> xAxis >> width;
  auto number = [&](const std::string& text, long long& value) {
    const char* end = text.data() + text.size();
    const auto [stop, error] = std::from_chars(text.data(), end, value);
    if (text.empty() || error != std::errc() || stop != end) {
      fail(path, "Radiance HDR resolution line '" + resolution.substr(0, 40) + "' is not valid");
    }
  };
  number(height, header.height);
  number(width, header.width);
  const auto isAxis = [](const std::string& a, char axis) {
    return a.size() == 2 && (a[0] == '-' || a[0] == '+') && a[1] == axis;
  };
  header.rotated = isAxis(yAxis, 'X') && isAxis(xAxis, 'Y');
  if (!header.rotated && !(isAxis(yAxis, 'Y') && isAxis(xAxis, 'X'))) {
    fail(path, "Radiance HDR resolution line '" + resolution.substr(0, 40) + "' is not valid");
  }
  header.bottomUp = yAxis == "+Y";
  header.rightToLeft = xAxis == "-X";
  return header;
}

// One scanline of `width` RGBE pixels from bytes[pos...] into out[4 width]; false if it runs
// past the end of the file or a run past the end of the scanline.
bool readScanline(const std::string& bytes, std::size_t& pos, long long width, std::uint8_t* out) {
  const auto* b = reinterpret_cast<const std::uint8_t*>(bytes.data());
  const std::size_t size = bytes.size();
  const bool runLength = width >= kMinRunLengthWidth && width <= kMaxRunLengthWidth &&
                         pos + 4 <= size && b[pos] == 2 && b[pos + 1] == 2 &&
                         (b[pos + 2] & 0x80) == 0;
  if (!runLength) {
    const std::size_t flat = 4 * static_cast<std::size_t>(width);
    if (size - pos < flat) return false;
    std::memcpy(out, b + pos, flat);
    pos += flat;
    return true;
  }
  if ((b[pos + 2] << 8 | b[pos + 3]) != width) return false;
  pos += 4;
  for (int c = 0; c < 4; ++c) {
    for (long long x = 0; x < width;) {
      if (pos >= size) return false;
      const int count = b[pos++];
      const bool run = count > 128;
      const long long n = run ? count - 128 : count;
      if (n == 0 || x + n > width || (run ? 1 : static_cast<std::size_t>(n)) > size - pos) {
        return false;
      }
      for (long long i = 0; i < n; ++i) out[4 * (x + i) + c] = b[run ? pos : pos + i];
      pos += run ? 1 : static_cast<std::size_t>(n);
      x += n;
    }
  }
  return true;
}

// Walter's rgbe.c conversion (www.graphics.cornell.edu/~bjw/rgbe.html), as OpenImageIO's reader
// has it: the mantissa times 2^(e - 136), no half-step offset, so files read as before.
glm::vec3 rgbeToFloat(const std::uint8_t* p) {
  if (p[3] == 0) return glm::vec3(0.0f);
  const float f = std::ldexp(1.0f, p[3] - (128 + 8));
  return glm::vec3(p[0] * f, p[1] * f, p[2] * f);
}

void floatToRgbe(const glm::vec3& c, std::uint8_t* p) {
  // Infinities as the largest float, so that the exponent stays defined.
  const glm::vec3 finite = glm::min(c, glm::vec3(std::numeric_limits<float>::max()));
  const float v = std::max(finite.x, std::max(finite.y, finite.z));
  if (!(v >= 1e-32f)) {  // NaN and negative too
    p[0] = p[1] = p[2] = p[3] = 0;
    return;
  }
  int e;
  const float scale = std::frexp(v, &e) * 256.0f / v;
  for (int k = 0; k < 3; ++k) {
    p[k] = static_cast<std::uint8_t>(std::clamp(finite[k] * scale, 0.0f, 255.0f));
  }
  p[3] = static_cast<std::uint8_t>(std::clamp(e + 128, 0, 255));
}

// Walter's RLE of one component of a scanline: runs of at least 4 equal bytes as runs, the rest
// as literal dumps of at most 128 bytes.
void encodeComponent(const std::uint8_t* data, int width, std::string& out) {
  constexpr int kMinRun = 4;
  for (int cur = 0; cur < width;) {
    int begRun = cur, runCount = 0, oldRunCount = 0;
    while (runCount < kMinRun && begRun < width) {
      begRun += runCount;
      oldRunCount = runCount;
      runCount = 1;
      while (begRun + runCount < width && runCount < 127 &&
             data[4 * begRun] == data[4 * (begRun + runCount)]) {
        ++runCount;
      }
    }
    // A short run just before the long one is cheaper as a run.
    if (oldRunCount > 1 && oldRunCount == begRun - cur) {
      out += static_cast<char>(128 + oldRunCount);
      out += static_cast<char>(data[4 * cur]);
      cur = begRun;
    }
    while (cur < begRun) {
      const int dump = std::min(begRun - cur, 128);
      out += static_cast<char>(dump);
      for (int i = 0; i < dump; ++i) out += static_cast<char>(data[4 * (cur + i)]);
      cur += dump;
    }
    if (runCount >= kMinRun) {
      out += static_cast<char>(128 + runCount);
      out += static_cast<char>(data[4 * begRun]);
      cur += runCount;
    }
  }
}

}  // namespace

std::optional<DecodedImage> readRgbe(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.rfind("#?", 0) != 0) fail(path, "not a Radiance HDR file");
  std::size_t pos = 0;
  const Header header = readHeader(path, bytes, pos);
  // Rotated pictures: OpenImageIO's reader, as before (image_format.h).
  if (header.rotated) return std::nullopt;
  checkDeclaredImageSize(path, "hdr", header.width, header.height, 3, true, bytes.size());
  DecodedImage decoded;
  ImageRgb& image = decoded.image;
  image.width = static_cast<int>(header.width);
  image.height = static_cast<int>(header.height);
  image.pixels.resize(static_cast<std::size_t>(image.width) * image.height);
  std::vector<std::uint8_t> row(4 * static_cast<std::size_t>(image.width));
  for (int y = 0; y < image.height; ++y) {
    if (!readScanline(bytes, pos, image.width, row.data())) {
      fail(path, "Radiance HDR scanline " + std::to_string(y) + " of " +
                     std::to_string(image.height) + " is truncated or corrupt");
    }
    const int top = header.bottomUp ? image.height - 1 - y : y;
    for (int x = 0; x < image.width; ++x) {
      image.at(header.rightToLeft ? image.width - 1 - x : x, top) = rgbeToFloat(&row[4 * x]);
    }
  }
  return decoded;
}

void writeRgbe(const std::string& path, const PixelsToWrite& pixels) {
  std::string out = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(pixels.height) +
                    " +X " + std::to_string(pixels.width) + "\n";
  const int w = pixels.width;
  const auto* linear = reinterpret_cast<const glm::vec3*>(pixels.linear);
  const bool runLength = w >= kMinRunLengthWidth && w <= kMaxRunLengthWidth;
  std::vector<std::uint8_t> row(4 * static_cast<std::size_t>(w));
  for (int y = 0; y < pixels.height; ++y) {
    for (int x = 0; x < w; ++x)
      floatToRgbe(linear[static_cast<std::size_t>(y) * w + x], &row[4 * x]);
    if (!runLength) {
      out.append(reinterpret_cast<const char*>(row.data()), row.size());
      continue;
    }
    out += {2, 2, static_cast<char>(w >> 8), static_cast<char>(w & 255)};
    for (int c = 0; c < 4; ++c) encodeComponent(row.data() + c, w, out);
  }
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file.write(out.data(), static_cast<std::streamsize>(out.size()));
  if (!file.flush()) fail(path, "cannot write");
}

}  // namespace sss
