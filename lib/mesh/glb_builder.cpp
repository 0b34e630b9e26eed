#include "mesh/glb_builder.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>

#include <glm/common.hpp>

#include "core/error.h"
#include "mesh/glb_chunks.h"
#include "mesh/gltf_document.h"

namespace sss {
namespace {

static_assert(std::endian::native == std::endian::little, "GLB is little-endian: bytes are copied");

using gltf::kByte, gltf::kFloat, gltf::kShort, gltf::kUnsignedInt, gltf::kUnsignedShort;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

void putU32(std::string& out, std::uint32_t v) {
  char bytes[4];
  std::memcpy(bytes, &v, 4);
  out.append(bytes, 4);
}

}  // namespace

int GlbBinary::addView(const void* data, std::size_t bytes, int target) {
  const std::size_t offset = bin_.size();
  bin_.append(static_cast<const char*>(data), bytes);
  bin_.resize((bin_.size() + 3) / 4 * 4, '\0');
  Json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
  if (target != 0) view["target"] = target;
  bufferViews_.push_back(view);
  return static_cast<int>(bufferViews_.size()) - 1;
}

int GlbBinary::addVec3(const std::vector<glm::vec3>& values, bool withBounds) {
  Json accessor = {{"bufferView", addView(values.data(), values.size() * 12, kArrayBuffer)},
                   {"componentType", kFloat},
                   {"count", values.size()},
                   {"type", "VEC3"}};
  if (withBounds) {
    glm::vec3 lo = values[0], hi = values[0];
    for (const glm::vec3& v : values) {
      lo = glm::min(lo, v);
      hi = glm::max(hi, v);
    }
    accessor["min"] = {lo.x, lo.y, lo.z};
    accessor["max"] = {hi.x, hi.y, hi.z};
  }
  accessors_.push_back(accessor);
  return static_cast<int>(accessors_.size()) - 1;
}

int GlbBinary::addIntegerVec4(const std::vector<int16_t>& components, int componentType,
                              bool normalized) {
  const std::size_t count = components.size() / 4;
  int view = 0;
  if (componentType == kShort || componentType == kUnsignedShort) {
    view = addView(components.data(), count * 8, kArrayBuffer);
  } else {
    std::vector<int8_t> bytes(components.size());
    for (std::size_t i = 0; i < components.size(); ++i)
      bytes[i] = static_cast<int8_t>(components[i]);
    view = addView(bytes.data(), count * 4, kArrayBuffer);
  }
  Json accessor = {{"bufferView", view}, {"componentType", componentType}};
  if (normalized) accessor["normalized"] = true;
  accessor["count"] = count;
  accessor["type"] = "VEC4";
  accessors_.push_back(accessor);
  return static_cast<int>(accessors_.size()) - 1;
}

// A float vertex attribute of `components` per element (`type`: "VEC2", "VEC4").
int GlbBinary::addFloats(const float* values, std::size_t elements, int components,
                         const char* type) {
  const std::size_t bytes = elements * std::size_t(components) * 4;
  accessors_.push_back({{"bufferView", addView(values, bytes, kArrayBuffer)},
                        {"componentType", kFloat},
                        {"count", elements},
                        {"type", type}});
  return static_cast<int>(accessors_.size()) - 1;
}

int GlbBinary::addVec2(const std::vector<glm::vec2>& values) {
  return addFloats(reinterpret_cast<const float*>(values.data()), values.size(), 2, "VEC2");
}

int GlbBinary::addVec4(const std::vector<glm::vec4>& values) {
  return addFloats(reinterpret_cast<const float*>(values.data()), values.size(), 4, "VEC4");
}

int GlbBinary::addIndices(const std::vector<glm::uvec3>& triangles) {
  const int view = addView(triangles.data(), triangles.size() * 12, kElementArrayBuffer);
  accessors_.push_back({{"bufferView", view},
                        {"componentType", kUnsignedInt},
                        {"count", triangles.size() * 3},
                        {"type", "SCALAR"}});
  return static_cast<int>(accessors_.size()) - 1;
}

std::string encodeGlb(const std::string& path, GlbBinary::Json document, const GlbBinary& binary) {
  document["buffers"] = {{{"byteLength", binary.bin().size()}}};
  document["bufferViews"] = binary.bufferViews();
  document["accessors"] = binary.accessors();
  std::string json;
  try {
    json = document.dump();
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("cannot encode the glTF JSON: ") + e.what());
  }
  json.resize((json.size() + 3) / 4 * 4, ' ');
  const std::string& bin = binary.bin();
  const std::uint64_t total = 12 + 8 + json.size() + 8 + bin.size();
  if (total > std::numeric_limits<std::uint32_t>::max()) {
    fail(path, "the mesh needs " + std::to_string(total) + " bytes, over GLB's 4 GiB");
  }
  std::string out;
  out.reserve(total);
  putU32(out, kGlbMagic);
  putU32(out, 2);
  putU32(out, static_cast<std::uint32_t>(total));
  putU32(out, static_cast<std::uint32_t>(json.size()));
  putU32(out, kChunkJson);
  out += json;
  putU32(out, static_cast<std::uint32_t>(bin.size()));
  putU32(out, kChunkBin);
  out += bin;
  return out;
}

}  // namespace sss
