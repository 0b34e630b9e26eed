// Writing a GLB (glTF 2.0 specification, section 4.4): the BIN chunk with the bufferViews and
// accessors that describe it, then the 12-byte header, the JSON chunk padded with spaces and the
// BIN chunk padded with zeros, both 4-byte aligned. Shared by the GLB writers of this library
// (baked_glb.h, lightmapped_glb.h); glb_chunks.h reads the container back.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <nlohmann/json.hpp>

namespace sss {

class GlbBinary {
 public:
  using Json = nlohmann::ordered_json;

  // Raw bytes in a bufferView of their own (target 0: none, as for an image); its index.
  int addView(const void* data, std::size_t bytes, int target = 0);
  // Float VEC3 / VEC2 / VEC4 vertex attributes; POSITION needs its bounds (section 3.7.2.1). The
  // accessor's index.
  int addVec3(const std::vector<glm::vec3>& values, bool withBounds);
  int addVec2(const std::vector<glm::vec2>& values);
  int addVec4(const std::vector<glm::vec4>& values);
  // A VEC4 vertex attribute of `componentType` kShort, kUnsignedShort (each value's 16 bits) or
  // kByte (each value in [-128, 127]),
  // `normalized` (the GPU reads q / 32767 or q / 127) or not, from its elements' four components
  // in a row. VEC4, not VEC3: vertex attributes are 4-byte aligned (section 3.6.2.4), so a VEC3
  // of them would take a fourth component's bytes anyway.
  int addIntegerVec4(const std::vector<int16_t>& components, int componentType, bool normalized);
  // Triangle corners as unsigned int indices.
  int addIndices(const std::vector<glm::uvec3>& triangles);

  const std::string& bin() const { return bin_; }
  const Json& bufferViews() const { return bufferViews_; }
  const Json& accessors() const { return accessors_; }

 private:
  int addFloats(const float* values, std::size_t elements, int components, const char* type);

  std::string bin_;
  Json bufferViews_ = Json::array();
  Json accessors_ = Json::array();
};

// The GLB file's bytes for `document` (its "buffers", "bufferViews" and "accessors" are set from
// `binary` here). Throws Error naming `path` when the JSON cannot be encoded or the file would
// pass GLB's 4 GiB.
std::string encodeGlb(const std::string& path, GlbBinary::Json document, const GlbBinary& binary);

}  // namespace sss
