// A walk over an OpenEXR file's headers before OpenEXR opens it. While it opens a file,
// OpenEXR allocates what the headers declare before comparing it with the file: an attribute's
// value (the fuzzer's 553-byte file declared a 1.7 GB attribute), the chunk offset table (8 bytes
// per chunk of the data window) and blocks of decoded scanlines or tiles. So
// each attribute is followed as OpenEXR reads it, and each part's data window is checked against
// kMaxImagePixels (image/image.h), its offset table against the file size and its block size
// against kMaxExrChunkBytes, all before OpenEXR (or OpenImageIO) reads the file.
#pragma once

#include <cstdint>
#include <string>

namespace sss {

// The most bytes one decoded chunk may take (a row of tiles, or 256 scanlines as OpenImageIO
// reads them): 512 MiB, a 16384-pixel-wide block of 32 float channels.
inline constexpr std::uint64_t kMaxExrChunkBytes = std::uint64_t{1} << 29;

// Files that do not start with the OpenEXR magic number are left alone. Throws
// Error("<path>: EXR header ...") for an attribute larger than the rest of the file, a header
// that is not terminated within the file, or a part whose data window exceeds the limits above.
void checkExrHeader(const std::string& path);

}  // namespace sss
