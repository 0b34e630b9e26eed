#include "image/image_limits.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "core/error.h"

namespace sss {

unsigned long long minimumImageFileBytes(const std::string& format, long long width,
                                         long long height, int channels, bool floatSamples) {
  const unsigned long long w = static_cast<unsigned long long>(std::max(width, 0LL));
  const unsigned long long h = static_cast<unsigned long long>(std::max(height, 0LL));
  const unsigned long long c = static_cast<unsigned long long>(std::max(channels, 0));
  if (format == "hdr") {
    // Widths outside [8, 32767] cannot be run-length encoded.
    const unsigned long long row = w < 8 || w > 32767 ? 4 * w : 4 + 8 * ((w + 126) / 127);
    return h * row;
  }
  if (format == "pnm") return floatSamples ? w * h * c * 4 : w * h * c / 8;
  return w * h / 65536;
}

void checkDeclaredImageSize(const std::string& path, const std::string& format, long long width,
                            long long height, int channels, bool floatSamples,
                            long long fileBytes) {
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  if (width <= 0 || height <= 0) fail(path, "image has zero size (" + size + ")");
  if (width > kMaxImagePixels / height) {
    fail(path, "header declares " + size + " pixels, more than the " +
                   std::to_string(kMaxImagePixels) + " (2^28) an image may have");
  }
  if (fileBytes < 0) {
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(path, ec);
    if (ec) return;  // the reader reports an unreadable file
    fileBytes = static_cast<long long>(bytes);
  }
  const unsigned long long needed =
      minimumImageFileBytes(format, width, height, channels, floatSamples);
  if (static_cast<unsigned long long>(fileBytes) < needed) {
    fail(path, "header declares " + size + " pixels, which take at least " +
                   std::to_string(needed) + " bytes, but the file has " +
                   std::to_string(fileBytes) + " (truncated?)");
  }
}

}  // namespace sss
