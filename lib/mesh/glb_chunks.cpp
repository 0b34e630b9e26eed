#include "mesh/glb_chunks.h"

#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/error.h"

namespace sss {
namespace {}  // namespace

GlbChunks readGlbChunks(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) fail(path, "cannot open");
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) fail(path, "cannot read its size");
  char header[20];
  if (size < 20 || !file.read(header, 20)) {
    fail(path, "not a GLB: " + std::to_string(size) + " bytes, under a header and one chunk");
  }
  if (readU32(header) != kGlbMagic) fail(path, "not a GLB: no 'glTF' magic");
  if (readU32(header + 4) != 2) {
    fail(path, "GLB version " + std::to_string(readU32(header + 4)) + ", not 2");
  }
  if (readU32(header + 8) != size) {
    fail(path, "GLB header declares " + std::to_string(readU32(header + 8)) +
                   " bytes, the file has " + std::to_string(size) + " (truncated?)");
  }
  const std::uint64_t jsonLength = readU32(header + 12);
  if (readU32(header + 16) != kChunkJson) fail(path, "the first GLB chunk is not JSON");
  if (jsonLength % 4 != 0 || 20 + jsonLength > size) {
    fail(path, "JSON chunk of " + std::to_string(jsonLength) + " bytes does not fit the file");
  }
  GlbChunks chunks;
  chunks.json.resize(jsonLength);
  if (!file.read(chunks.json.data(), static_cast<std::streamsize>(jsonLength))) {
    fail(path, "cannot read the JSON chunk");
  }
  if (20 + jsonLength == size) return chunks;  // no BIN chunk
  char binHeader[8];
  if (size - 20 - jsonLength < 8 || !file.read(binHeader, 8)) fail(path, "truncated BIN chunk");
  const std::uint64_t binLength = readU32(binHeader);
  if (readU32(binHeader + 4) != kChunkBin) fail(path, "the second GLB chunk is not BIN");
  if (binLength % 4 != 0 || 28 + jsonLength + binLength > size) {
    fail(path, "BIN chunk of " + std::to_string(binLength) + " bytes does not fit the file");
  }
  chunks.bin.resize(binLength);
  if (!file.read(chunks.bin.data(), static_cast<std::streamsize>(binLength))) {
    fail(path, "cannot read the BIN chunk");
  }
  return chunks;
}

}  // namespace sss
