// The largest image a reader accepts (image.h, exr_header.h).
#pragma once

namespace sss {

// What a header may declare, checked before any pixel is allocated: at most kMaxImagePixels,
// 2^28 (16384 x 16384, twice a 16K equirect, the largest common HDRI; the reader's two float RGB
// buffers then take 6 GiB), and no more than the file's size can hold (minimumImageFileBytes).
inline constexpr long long kMaxImagePixels = 1LL << 28;

}  // namespace sss
