// The GLB container (glTF 2.0 specification, section 4.4 "GLB File Format Specification"): a
// 12-byte header (magic "glTF", version 2, total length), a JSON chunk, then optionally a BIN
// chunk, each chunk an 8-byte header (length, type) and its data padded to 4 bytes. Shared by the
// baked GLB reader (baked_glb.h) and the glTF scene reader (gltf_reader.h).
#pragma once

#include <cstdint>
#include <cstring>
#include <string>

namespace sss {

// A little-endian 32-bit word at p (the GLB header's and chunks' fields, accessor data).
inline std::uint32_t readU32(const char* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

inline constexpr std::uint32_t kGlbMagic = 0x46546C67;   // "glTF"
inline constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
inline constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"

// The GLB's chunks, their lengths checked against the file.
struct GlbChunks {
  std::string json;
  std::string bin;  // empty when the file has no BIN chunk
};

// Reads `path`'s header and chunks: the declared total length must be the file's size and each
// chunk's length must fit in what follows it (checked before anything is allocated). Bytes after
// the BIN chunk are ignored. Throws Error "<path>: <problem>".
GlbChunks readGlbChunks(const std::string& path);

}  // namespace sss
