#include "image/exr_header.h"

#include <algorithm>
#include <cstring>
#include <fstream>
#include <string_view>

#include "core/error.h"
#include "image/image_limits.h"

namespace sss {
namespace {

// The layout (openexr.com, "OpenEXR File Layout"): the magic number, a 4-byte version field (bit
// 9: a single tiled part, bit 12: several parts), then each part's header as attributes (name and
// type name null-terminated, at most 255 characters, an int32 size, the value) ending with an
// empty name; a multi-part file ends its headers with one more empty name. All little-endian.
constexpr unsigned char kMagic[4] = {0x76, 0x2f, 0x31, 0x01};
constexpr std::uint32_t kTiledFlag = 1u << 9;
constexpr std::uint32_t kMultiPartFlag = 1u << 12;
constexpr std::size_t kMaxNameLength = 255;

// The bytes OpenEXR 3.1 reads for a value of a fixed-size type, whatever the size field says.
std::uint64_t fixedValueBytes(std::string_view type) {
  static constexpr std::pair<std::string_view, std::uint64_t> kSizes[] = {
      {"box2i", 16},      {"box2f", 16},   {"chromaticities", 32},
      {"compression", 1}, {"double", 8},   {"envmap", 1},
      {"float", 4},       {"int", 4},      {"keycode", 28},
      {"lineOrder", 1},   {"m33f", 36},    {"m33d", 72},
      {"m44f", 64},       {"m44d", 128},   {"rational", 8},
      {"tiledesc", 9},    {"timecode", 8}, {"v2i", 8},
      {"v2f", 8},         {"v2d", 16},     {"v3i", 12},
      {"v3f", 12},        {"v3d", 24},     {"deepImageState", 1}};
  for (const auto& [name, bytes] : kSizes) {
    if (name == type) return bytes;
  }
  return 0;
}

// Scanlines per chunk for each compression (OpenEXR's numLinesInBuffer); unknown ones: the most.
std::uint64_t linesPerChunk(int compression) {
  static constexpr std::uint64_t kLines[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
  return compression >= 0 && compression < 10 ? kLines[compression] : 256;
}

// What the checks need from one part's header.
struct Part {
  bool hasWindow = false;
  std::int64_t xMin = 0, yMin = 0, xMax = 0, yMax = 0;
  int compression = -1;
  bool hasTiles = false;
  std::uint64_t tileWidth = 0, tileHeight = 0;
  std::int64_t chunkCount = -1;     // multi-part files state it
  std::uint64_t bytesPerPixel = 0;  // over the channels: half 2, float and uint 4
};

class HeaderWalk {
 public:
  HeaderWalk(const std::string& path, std::ifstream& in, std::uint64_t size)
      : path_(path), in_(in), size_(size) {}

  // One header's attributes, up to its terminating empty name.
  Part header() {
    Part part;
    for (std::string name = text("attribute name"); !name.empty(); name = text("attribute name")) {
      const std::string type = text("attribute type");
      const std::int32_t declared = int32();
      if (declared < 0) fail(path_, "EXR header attribute '" + name + "' has a negative size");
      attribute(name, type, static_cast<std::uint64_t>(declared), part);
    }
    return part;
  }

  bool atEmptyName() {
    const int c = in_.peek();
    if (c == std::char_traits<char>::eof()) truncated();
    return c == '\0';
  }

 private:
  [[noreturn]] void truncated() const {
    fail(path_, "EXR header runs past the end of the file (truncated)");
  }
  std::uint64_t left() const {
    const std::uint64_t at = static_cast<std::uint64_t>(in_.tellg());
    return at < size_ ? size_ - at : 0;
  }
  // Throws unless `bytes` more are in the file (before anything would allocate them).
  void need(const std::string& name, std::uint64_t bytes) const {
    if (bytes > left()) {
      fail(path_, "EXR header attribute '" + name + "' declares " + std::to_string(bytes) +
                      " bytes, but the file has " + std::to_string(left()) +
                      " left (truncated or corrupt)");
    }
  }
  void skip(const std::string& name, std::uint64_t bytes) {
    need(name, bytes);
    in_.seekg(static_cast<std::streamoff>(bytes), std::ios::cur);
  }
  std::string text(const char* what) {
    std::string s;
    for (char c; in_.get(c);) {
      if (c == '\0') return s;
      if (s.size() == kMaxNameLength) fail(path_, std::string("EXR header: ") + what + " too long");
      s += c;
    }
    truncated();
  }
  std::uint32_t uint32() {
    unsigned char b[4];
    if (!in_.read(reinterpret_cast<char*>(b), 4)) truncated();
    return b[0] | b[1] << 8 | b[2] << 16 | std::uint32_t{b[3]} << 24;
  }
  std::int32_t int32() { return static_cast<std::int32_t>(uint32()); }
  unsigned char byte() {
    char c;
    if (!in_.get(c)) truncated();
    return static_cast<unsigned char>(c);
  }

  void attribute(const std::string& name, const std::string& type, std::uint64_t declared,
                 Part& part);
  void channels(Part& part);

  const std::string& path_;
  std::ifstream& in_;
  std::uint64_t size_;
};

// Reads the value as OpenEXR does: fixed-size types take their size whatever the size field says,
// a channel list runs to its empty name, a preview holds 4 bytes a pixel after its size, and every
// other type (string, vectors, unknown types) is read into a buffer of the declared size.
void HeaderWalk::attribute(const std::string& name, const std::string& type, std::uint64_t declared,
                           Part& part) {
  if (type == "chlist") return channels(part);
  if (type == "preview") {
    const std::uint64_t width = uint32(), height = uint32();  // below 2^32: no overflow
    const std::uint64_t pixels = width * height;
    return skip(name, pixels > left() ? pixels : 4 * pixels);
  }
  if (type == "box2i" && name == "dataWindow") {
    part.hasWindow = true;
    part.xMin = int32();
    part.yMin = int32();
    part.xMax = int32();
    part.yMax = int32();
  } else if (type == "compression" && name == "compression") {
    part.compression = byte();
  } else if (type == "tiledesc" && name == "tiles") {
    part.hasTiles = true;
    part.tileWidth = uint32();
    part.tileHeight = uint32();
    byte();  // level and rounding modes
  } else if (type == "int" && name == "chunkCount") {
    part.chunkCount = int32();
  } else if (const std::uint64_t fixed = fixedValueBytes(type)) {
    skip(name, fixed);
  } else if (type == "stringvector") {
    // Strings of an int32 length each, within the declared size.
    need(name, declared);
    for (std::uint64_t read = 0; read < declared;) {
      const std::int32_t length = int32();
      read += 4;
      if (length < 0 || static_cast<std::uint64_t>(length) > declared - std::min(read, declared)) {
        fail(path_, "EXR header attribute '" + name + "' holds a string of " +
                        std::to_string(length) + " bytes, longer than the attribute");
      }
      skip(name, static_cast<std::uint64_t>(length));
      read += static_cast<std::uint64_t>(length);
    }
  } else {
    skip(name, declared);
  }
}

// Channels: a name, an int32 pixel type (0 uint, 1 half, 2 float), a byte and 3 padding bytes,
// two int32 sampling factors; an empty name ends the list.
void HeaderWalk::channels(Part& part) {
  for (std::string channel = text("channel name"); !channel.empty();
       channel = text("channel name")) {
    const std::int32_t pixelType = int32();
    for (int i = 0; i < 12; ++i) byte();
    part.bytesPerPixel += pixelType == 1 ? 2 : 4;
  }
}

// The data window against kMaxImagePixels, the chunk offset table (8 bytes a chunk, read before
// any pixel) against the file size, one decoded chunk against kMaxExrChunkBytes.
void checkPart(const std::string& path, const Part& part, bool tiled, std::uint64_t fileSize) {
  // No window, or an empty one: OpenEXR refuses the header itself.
  if (!part.hasWindow || part.xMax < part.xMin || part.yMax < part.yMin) return;
  const std::uint64_t width = part.xMax - part.xMin + 1, height = part.yMax - part.yMin + 1;
  const std::string window = std::to_string(width) + "x" + std::to_string(height);
  if (width > static_cast<std::uint64_t>(kMaxImagePixels) / height) {
    fail(path, "EXR header declares a " + window + " data window, more than the " +
                   std::to_string(kMaxImagePixels) + " (2^28) pixels an image may have");
  }
  // The buffers hold whole tiles, or whole blocks of scanlines, even where the data window is
  // smaller: OpenEXR decodes a chunk at a time, OpenImageIO a row of tiles or 256 scanlines
  // (measured: a 65536-pixel-wide float RGB image allocates 65536 x 256 x 12 bytes).
  std::uint64_t chunks, chunkPixels;
  if (tiled && part.tileWidth > 0 && part.tileHeight > 0) {
    const std::uint64_t across = (width + part.tileWidth - 1) / part.tileWidth;
    chunks = across * ((height + part.tileHeight - 1) / part.tileHeight);
    chunkPixels = across * part.tileWidth * part.tileHeight;
  } else {
    const std::uint64_t lines = linesPerChunk(part.compression);
    chunks = (height + lines - 1) / lines;
    chunkPixels = width * 256;
  }
  chunks = std::max<std::uint64_t>(chunks, std::max<std::int64_t>(part.chunkCount, 0));
  if (chunks > fileSize / 8) {
    fail(path, "EXR header declares a " + window + " data window in " + std::to_string(chunks) +
                   " chunks, whose offset table alone takes " + std::to_string(8 * chunks) +
                   " bytes, but the file has " + std::to_string(fileSize) + " (truncated?)");
  }
  const std::uint64_t bytesPerPixel = std::max<std::uint64_t>(part.bytesPerPixel, 1);
  if (chunkPixels > kMaxExrChunkBytes / bytesPerPixel) {
    fail(path, "EXR header declares chunks of " + std::to_string(chunkPixels) + " pixels of " +
                   std::to_string(bytesPerPixel) + " bytes (" + window +
                   " data window), more than the " + std::to_string(kMaxExrChunkBytes) +
                   " bytes (512 MiB) a decoded chunk may take");
  }
}

}  // namespace

void checkExrHeader(const std::string& path) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return;  // the reader reports it
  const std::uint64_t size = static_cast<std::uint64_t>(in.tellg());
  in.seekg(0);
  unsigned char start[8];
  if (!in.read(reinterpret_cast<char*>(start), 8) || std::memcmp(start, kMagic, 4) != 0) return;
  const std::uint32_t version =
      start[4] | start[5] << 8 | start[6] << 16 | std::uint32_t{start[7]} << 24;
  HeaderWalk walk(path, in, size);
  if (!(version & kMultiPartFlag)) {
    const Part part = walk.header();
    checkPart(path, part, (version & kTiledFlag) && part.hasTiles, size);
    return;
  }
  do {
    const Part part = walk.header();
    checkPart(path, part, part.hasTiles, size);
  } while (!walk.atEmptyName());
}

}  // namespace sss
