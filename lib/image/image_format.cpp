#include "image/image_format.h"

#include <cstring>
#include <fstream>

#include "core/file_extension.h"

namespace sss {

ImageBackend readerFor(const std::string& path) {
  // The magic numbers: OpenEXR's 0x762f3101 (openexr.com, "OpenEXR File Layout"), PNG's 8-byte
  // signature (PNG specification, 5.2), Radiance's "#?" (Ward, "The RADIANCE Picture File
  // Format").
  static constexpr unsigned char kExr[4] = {0x76, 0x2f, 0x31, 0x01};
  static constexpr unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  unsigned char start[8] = {};
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(start), sizeof start);
  const std::streamsize got = in.gcount();
  if (got >= 4 && std::memcmp(start, kExr, 4) == 0) return ImageBackend::OpenExr;
  if (got == 8 && std::memcmp(start, kPng, 8) == 0) return ImageBackend::Png;
  if (got >= 2 && start[0] == '#' && start[1] == '?') return ImageBackend::RadianceHdr;
  return ImageBackend::OpenImageIO;
}

ImageBackend writerFor(const std::string& path) {
  const std::string ext = lowerExtension(path);
  if (ext == "exr") return ImageBackend::OpenExr;
  if (ext == "png") return ImageBackend::Png;
  if (ext == "hdr") return ImageBackend::RadianceHdr;
  return ImageBackend::OpenImageIO;
}

bool isFloatImageExtension(const std::string& extension) {
  return extension == "exr" || extension == "hdr" || extension == "pfm" || extension == "tif" ||
         extension == "tiff";
}

}  // namespace sss
