// The largest image a reader accepts, and the check every reader makes of a header's declared
// size before allocating its pixels (a header may lie).
#pragma once

#include <cstdint>
#include <string>

namespace sss {

// What a header may declare, checked before any pixel is allocated: at most kMaxImagePixels,
// 2^28 (16384 x 16384, twice a 16K equirect, the largest common HDRI; the reader's two float RGB
// buffers then take 6 GiB), and no more than the file's size can hold (minimumImageFileBytes).
inline constexpr long long kMaxImagePixels = 1LL << 28;

// The fewest bytes a file of format `format` ("hdr", "pnm", "openexr", ... as OpenImageIO names
// them) can hold a width x height image with `channels` channels in: Radiance HDR scanlines are
// flat (4 bytes a pixel) or run-length encoded (a 4-byte header, then at least 2 bytes per 127
// pixels in each of 4 channels); PFM holds every float and other PNM at least a bit per sample;
// the formats that compress get a floor of 1 byte per 2^16 pixels (the most, DWAB-compressed EXR,
// was measured at 2,800 pixels a byte on a constant 4096 x 4096 image). Header bytes are not
// counted.
unsigned long long minimumImageFileBytes(const std::string& format, long long width,
                                         long long height, int channels, bool floatSamples);

// Throws Error naming the file for a header that declares no pixels ("image has zero size"), more
// than kMaxImagePixels, or more than fileBytes can hold (fileBytes < 0: the file's size on disk).
void checkDeclaredImageSize(const std::string& path, const std::string& format, long long width,
                            long long height, int channels, bool floatSamples,
                            long long fileBytes = -1);

}  // namespace sss
